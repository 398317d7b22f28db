// mechgen zmp: the floor's reaction on the ground body (support foot) and its centre of pressure
// (ZMP) along the sole over a sweep, with the margins to the heel and the toe
// (runtime/analysis/ground_reaction.hpp).
#include <cmath>
#include <iostream>

#include "analysis/ground_reaction.hpp"
#include "cli/command.hpp"
#include "cli/sweep_source.hpp"
#include "report/csv_table.hpp"

namespace mechgen::cli {

namespace {

const std::string kZmpHelp =
    std::string(
        R"(usage: mechgen zmp MODEL.yaml [--csv FILE.csv | --solver S --samples N --t0 T0 --t1 T1]
                  [--set NAME=VALUE]... [--heel POINT] [--toe POINT] [--out FILE.csv]

The force and moment the floor exerts on the ground body (the support foot: it balances every
joint, driver and applied load on it, and its own weight when it has a mass), and the centre of
pressure (ZMP) on the sole, the segment heel -> toe: its distance from the heel, the margins to
the heel and to the toe (negative: outside the sole, the foot tips), and the smallest margin over
the run. Checked at every sample against the same reaction from the momentum rate of all bodies.
)") +
    kSweepSourceHelp +
    R"(  --heel POINT, --toe POINT  the sole's ends, points of the ground body (default: its two
                      points farthest apart, the heel the one with the smaller x)
  --out FILE.csv      t, reaction.fx, reaction.fy, reaction.m (about the ground origin),
                      reaction.normal, zmp, heel, toe (the sole's ends: 0 and its length),
                      heel_margin, toe_margin
)";

int run_zmp(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  const Model model = load_model(path);
  const SweepSource sweep = sweep_source(model, args);
  if (sweep.rows.empty()) throw UsageError("the sweep has no samples");
  const analysis::ZmpReport report = analysis::zmp_over(
      model, sweep.parameters, sweep.columns, sweep.rows, args.get("--heel"), args.get("--toe"));

  std::cout << "zmp " << model.name << ": sole " << report.heel << " -> " << report.toe << " ("
            << fixed(report.sole_length, 4) << " m), " << report.samples.size() << " samples ("
            << sweep.label << ")\n";
  double zmp_min = INFINITY, zmp_max = -INFINITY;
  for (const analysis::ZmpSample& s : report.samples)
    zmp_min = std::min(zmp_min, s.zmp), zmp_max = std::max(zmp_max, s.zmp);
  std::cout << "  ZMP from the heel: " << fixed(zmp_min, 4) << " .. " << fixed(zmp_max, 4)
            << " m\n";
  std::cout << "  on the sole: " << report.inside << " of " << report.samples.size() << " samples";
  if (report.inside > 0)
    std::cout << ", t = " << fixed(report.inside_t0, 4) << " .. " << fixed(report.inside_t1, 4)
              << " s";
  std::cout << "\n";
  std::cout << "  smallest normal force: " << fixed(report.min_normal, 4) << " N"
            << (report.min_normal > 0 ? "" : "  (the foot lifts: the ZMP means nothing there)")
            << "\n";
  std::cout << "  check: reaction from the joints vs from the momentum rate of all bodies: "
            << fixed(report.largest_disagreement, 3) << " N\n";
  std::cout << "ZMP margin: " << fixed(report.min_margin, 4) << " m to the "
            << report.min_margin_end << " at t = " << fixed(report.min_margin_t, 4) << " s ("
            << fixed(100 * report.min_margin / report.sole_length, 3) << " % of the sole; "
            << (report.min_margin >= 0 ? "always on the sole: it does not tip"
                                       : "off the sole at times: on this foot alone it tips")
            << ")\n";
  if (args.has("--out")) {
    report::CsvTable table;
    table.header = {"t",   "reaction.fx", "reaction.fy", "reaction.m",  "reaction.normal",
                    "zmp", "heel",        "toe",         "heel_margin", "toe_margin"};
    for (const analysis::ZmpSample& s : report.samples)
      table.rows.push_back({s.t, s.reaction.force.x(), s.reaction.force.y(), s.reaction.moment,
                            s.normal, s.zmp, 0.0, report.sole_length, s.heel_margin, s.toe_margin});
    const std::string out = args.get("--out");
    g_current_file = out;
    report::write_csv(table, out);
    std::cout << "wrote " << out << "\n";
  }
  return 0;
}

}  // namespace

Command zmp_command() {
  static const std::string help = kZmpHelp;
  std::vector<OptionSpec> options = sweep_source_options();
  options.insert(options.end(), {{"--heel", "", true}, {"--toe", "", true}, {"--out", "-o", true}});
  return {"zmp", "floor reaction on the support foot, ZMP and its margin to heel and toe",
          help.c_str(), options, &run_zmp};
}

}  // namespace mechgen::cli
