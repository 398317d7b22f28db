// mechgen loads: axial force, shear force, bending moment and stress of every bar over a sweep,
// the critical link and its safety factor (runtime/analysis/link_loads.hpp).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include "analysis/link_loads.hpp"
#include "cli/command.hpp"
#include "cli/sweep_source.hpp"
#include "report/atomic_output.hpp"
#include "report/csv_table.hpp"

namespace mechgen::cli {

namespace {

const std::string kLoadsHelp =
    std::string(
        R"(usage: mechgen loads MODEL.yaml [--csv FILE.csv | --solver S --samples N --t0 T0 --t1 T1]
                    [--set NAME=VALUE]... [--yield PA] [--out FILE.csv] [--over-time FILE.csv]
                    [--diagram LINK --diagram-out FILE.csv [--at T]]

For every bar (moving body with a cross-section: `section:` in the model, else its bar mass's
width x thickness), the axial force N, shear force V and bending moment M along it from the joint
forces, driver efforts, applied loads, gravity and d'Alembert inertia; the stresses
sigma = |N|/A + |M| c/I and tau (1.5 V/A for a rectangle); their maxima over the bar and the run
(with when and where: s from the bar's first axis point); the safety factor
yield / max(sigma, sqrt(3) tau) against the model's `material: {yield_strength}` (or --yield);
the critical link (lowest safety factor); and, with `material: {youngs_modulus}`, each bar's
Euler buckling load (pinned-pinned over its axis length, the section's smaller second moment)
against its largest compression. Rules: docs/link_loads.md.
)") +
    kSweepSourceHelp + R"(  --yield PA          yield strength for every bar without its own (Pa)
  --out FILE.csv      per-link maxima, one row per link
  --over-time FILE.csv  t and, per link, the largest |N|, |V|, |M| and sigma along it per sample
  --diagram LINK --diagram-out FILE.csv   N, V, M along one bar (columns s, N, V, M; a load
                      point appears twice, just before and just past it), at the sample of its
                      largest stress or at --at T (the nearest sample)
The equilibrium check (what is left past the last load of each bar, zero for a body in dynamic
equilibrium) is printed too.
)";

std::string mpa(double pa) {
  return fixed(pa / 1e6, 4);
}

void write_maxima(const std::string& path, const analysis::LinkLoadReport& report) {
  g_current_file = path;
  report::AtomicOutput output(path);
  std::ostream& file = output.stream();
  file << "link,section,length,area,inertia,fibre,N,N_t,N_s,V,V_t,V_s,M,M_t,M_s,sigma,sigma_t,"
          "sigma_s,tau,tau_t,tau_s,yield,safety,compression,compression_t,compression_s,"
          "youngs_modulus,buckling_inertia,buckling_load,buckling_safety\n";
  const auto num = [](double v) { return fixed(v, 17); };
  for (const analysis::LinkResult& l : report.links) {
    file << l.name << ",\"" << l.section.text << "\"," << num(l.length) << ","
         << num(l.section.area) << "," << num(l.section.inertia) << "," << num(l.section.fibre);
    for (const analysis::Peak* p : {&l.n, &l.v, &l.m, &l.sigma, &l.tau})
      file << "," << num(p->value) << "," << num(p->t) << "," << num(p->s);
    file << "," << num(l.section.yield) << "," << num(l.safety);
    for (const double v : {l.compression.value, l.compression.t, l.compression.s, l.section.modulus,
                           l.section.buckling_inertia, l.buckling_load, l.buckling_safety})
      file << "," << num(v);
    file << "\n";
  }
  output.commit();
}

void write_over_time(const std::string& path, const analysis::LinkLoadReport& report) {
  report::CsvTable table;
  table.header.push_back("t");
  for (const analysis::LinkResult& l : report.links)
    for (const char* what : {".N", ".V", ".M", ".sigma"}) table.header.push_back(l.name + what);
  for (size_t i = 0; i < report.t.size(); ++i) {
    std::vector<double> row{report.t[i]};
    for (const analysis::LinkResult& l : report.links)
      row.insert(row.end(), {l.n_t[i], l.v_t[i], l.m_t[i], l.sigma_t[i]});
    table.rows.push_back(std::move(row));
  }
  g_current_file = path;
  report::write_csv(table, path);
}

void write_diagram(const std::string& path, const analysis::BeamLoads& beam) {
  report::CsvTable table;
  table.header = {"s", "N", "V", "M"};
  for (const analysis::BeamStation& st : beam.stations) {
    if (st.n_before != st.n || st.v_before != st.v)
      table.rows.push_back({st.s, st.n_before, st.v_before, st.m});
    table.rows.push_back({st.s, st.n, st.v, st.m});
  }
  g_current_file = path;
  report::write_csv(table, path);
}

int run_loads(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  const Model model = load_model(path);
  analysis::LinkLoadOptions options;
  if (args.has("--yield")) {
    options.yield_override = args.number("--yield", 0);
    if (!(*options.yield_override > 0)) throw UsageError("--yield must be positive (Pa)");
  }
  const SweepSource sweep = sweep_source(model, args);
  if (sweep.rows.empty()) throw UsageError("the sweep has no samples");
  const analysis::LinkLoadReport report =
      analysis::link_loads(model, sweep.parameters, sweep.columns, sweep.rows, options);

  std::cout << "loads " << model.name << ": " << report.links.size() << " bars, " << report.t.size()
            << " samples (" << sweep.label << ")\n";
  std::vector<std::vector<std::string>> rows{{"link", "section", "L [m]", "|N| max [N]",
                                              "|V| max [N]", "|M| max [N m]", "sigma max [MPa]",
                                              "at t [s]", "s [m]", "tau max [MPa]", "safety",
                                              "compression [N]", "buckling [N]", "buckling SF"}};
  const auto factor = [](double v) {
    return std::isnan(v) ? std::string("-") : std::isinf(v) ? std::string("inf") : fixed(v, 4);
  };
  for (const analysis::LinkResult& l : report.links)
    rows.push_back({l.name, l.section.text, fixed(l.length, 4), fixed(std::abs(l.n.value), 4),
                    fixed(std::abs(l.v.value), 4), fixed(std::abs(l.m.value), 4),
                    mpa(l.sigma.value), fixed(l.sigma.t, 4), fixed(l.sigma.s, 4), mpa(l.tau.value),
                    factor(l.safety), fixed(std::abs(l.compression.value), 4),
                    std::isnan(l.buckling_load) ? "-" : fixed(l.buckling_load, 4),
                    factor(l.buckling_safety)});
  std::cout << table(rows, "  ");
  for (const std::string& s : report.skipped) std::cout << "  not a bar: " << s << "\n";
  if (report.critical >= 0) {
    const analysis::LinkResult& c = report.links[static_cast<size_t>(report.critical)];
    std::cout << "critical link: " << c.name << ", sigma " << mpa(c.sigma.value)
              << " MPa at t = " << fixed(c.sigma.t, 4) << " s, s = " << fixed(c.sigma.s, 4)
              << " m; ";
    if (std::isnan(c.safety))
      std::cout << "no yield strength (material: {yield_strength: ...} or --yield)\n";
    else
      std::cout << "yield " << mpa(c.section.yield) << " MPa, safety factor " << fixed(c.safety, 4)
                << "\n";
  }
  const analysis::LinkResult* buckling = nullptr;
  for (const analysis::LinkResult& l : report.links)
    if (!std::isnan(l.buckling_safety) &&
        (!buckling || l.buckling_safety < buckling->buckling_safety))
      buckling = &l;
  if (buckling)
    std::cout << "lowest buckling safety: " << buckling->name << ", compression "
              << fixed(std::abs(buckling->compression.value), 4)
              << " N at t = " << fixed(buckling->compression.t, 4) << " s against Euler's "
              << fixed(buckling->buckling_load, 4) << " N, safety factor "
              << factor(buckling->buckling_safety) << "\n";
  std::cout << "equilibrium check: largest force left past a bar's last load "
            << fixed(report.largest_end_residual, 3) << " N\n";
  if (args.has("--out")) {
    write_maxima(args.get("--out"), report);
    std::cout << "wrote " << args.get("--out") << "\n";
  }
  if (args.has("--diagram") != args.has("--diagram-out"))
    throw UsageError("--diagram LINK and --diagram-out FILE.csv go together");
  if (args.has("--at") && !args.has("--diagram")) throw UsageError("--at applies to --diagram");
  if (args.has("--diagram")) {
    const std::string link = args.get("--diagram");
    const auto result = std::find_if(report.links.begin(), report.links.end(),
                                     [&](const analysis::LinkResult& l) { return l.name == link; });
    if (result == report.links.end())
      throw UsageError("--diagram: '" + link + "' is not a bar of the report");
    const double at = args.number("--at", result->sigma.t);
    size_t nearest = 0;
    for (size_t i = 0; i < report.t.size(); ++i)
      if (std::abs(report.t[i] - at) < std::abs(report.t[nearest] - at)) nearest = i;
    write_diagram(args.get("--diagram-out"),
                  analysis::link_diagram(model, sweep.parameters, sweep.columns,
                                         sweep.rows[nearest], link, options.intervals));
    std::cout << "wrote " << args.get("--diagram-out") << " (" << link
              << " at t = " << fixed(report.t[nearest], 4) << " s)\n";
  }
  if (args.has("--over-time")) {
    write_over_time(args.get("--over-time"), report);
    std::cout << "wrote " << args.get("--over-time") << "\n";
  }
  return 0;
}

}  // namespace

Command loads_command() {
  static const std::string help = kLoadsHelp;
  std::vector<OptionSpec> options = sweep_source_options();
  options.insert(options.end(), {{"--yield", "", true},
                                 {"--out", "-o", true},
                                 {"--over-time", "", true},
                                 {"--diagram", "", true},
                                 {"--diagram-out", "", true},
                                 {"--at", "", true}});
  return {"loads", "axial, shear, bending and stress of every bar; critical link", help.c_str(),
          options, &run_loads};
}

}  // namespace mechgen::cli
