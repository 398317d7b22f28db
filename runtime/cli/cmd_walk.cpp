// mechgen walk: several steps of a biped in the world frame (runtime/analysis/walking.hpp).
#include <algorithm>
#include <cmath>
#include <iostream>

#include "analysis/walking.hpp"
#include "cli/command.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::cli {

namespace {

const char* const kWalkHelp =
    R"(usage: mechgen walk MODEL.yaml --steps N [--ramp SECONDS] [--set NAME=VALUE]...
                    [--samples N] [--mirror SUFFIX] --out FILE.csv

Walking, not one step: the model's step is one support phase (its ground body the support foot,
its one driver at constant speed); the support foot alternates every step (the other foot is the
ground body's mirror, named with SUFFIX), each new support foot stays where it landed, and the
whole walk is reported in the world frame (the first support foot's frame). Evaluated with the
generated kernel, the driver's motion fed directly.
  --steps N           support phases to walk (default 4)
  --ramp SECONDS      start from rest: the motor speed rises from 0 to the model's speed along a
                      quintic over this time (default 0: at speed from the start)
  --samples N         time resolution: N samples per steady step (default: the model's step)
  --mirror SUFFIX     the flying leg's bodies and points are named NAME + SUFFIX (default p)
  --set NAME=VALUE    overrides a model parameter (repeatable)
  --out FILE.csv      columns t, step, support (0: the model's ground body, 1: its mirror),
                      support.x; driver q, qd, qdd, effort; every body (both feet included),
                      point and joint force in the world frame. Two rows share t at each support
                      change.
Prints per step: support foot, where it stands, the hip's travel and height range, motor torque,
the largest joint force and its joint.
)";

int run_walk(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  if (!args.has("--out")) throw UsageError("missing --out FILE.csv");
  analysis::WalkOptions options;
  options.steps = args.integer("--steps", 4);
  if (options.steps < 1) throw UsageError("--steps must be at least 1");
  options.ramp = args.number("--ramp", 0);
  if (options.ramp < 0) throw UsageError("--ramp must be at least 0");
  options.samples_per_step = args.integer("--samples", 0);
  if (args.has("--samples") && options.samples_per_step < 2)
    throw UsageError("--samples must be at least 2");
  options.mirror_suffix = args.get("--mirror", "p");
  if (options.mirror_suffix.empty()) throw UsageError("--mirror needs a non-empty suffix");
  const Model model = load_model(path);
  options.parameters = model.default_parameters();
  apply_overrides(model, args.all("--set"), options.parameters);

  const auto start = std::chrono::steady_clock::now();
  const analysis::WalkResult walk = analysis::walk(model, options);
  const double elapsed = seconds_since(start);
  const std::string out = args.get("--out");
  g_current_file = out;
  write_csv(out, SweepResult{walk.columns, walk.rows});

  const size_t step = static_cast<size_t>(walk.column("step"));
  const size_t effort = static_cast<size_t>(walk.column(model.drivers.front().name + ".effort"));
  const size_t hip_x = static_cast<size_t>(walk.column(walk.hip_body + ".x"));
  const size_t hip_y = hip_x + 1;
  std::cout << "walk " << model.name << ": " << options.steps << " steps of "
            << fixed(walk.step_time, 4) << " s, ramp " << fixed(options.ramp, 4) << " s, "
            << walk.rows.size() << " rows, " << fixed(elapsed * 1e3, 3) << " ms -> " << out << "\n";
  std::vector<std::vector<std::string>> rows{
      {"step", "support", "support.x [m]", "t [s]", walk.hip_body + ".x [m]",
       walk.hip_body + ".y [m]", "peak |effort|", "rms effort", "peak |joint force| [N]"}};
  // Every joint's force columns (fx, then fy), for the largest joint load of each step.
  std::vector<std::pair<size_t, std::string>> joints;
  for (size_t c = 0; c + 1 < walk.columns.size(); ++c) {
    const std::string& name = walk.columns[c];
    if (name.size() > 3 && name.compare(name.size() - 3, 3, ".fx") == 0)
      joints.push_back({c, name.substr(0, name.size() - 3)});
  }
  for (int k = 0; k < options.steps; ++k) {
    double t0 = 0, t1 = 0, x0 = 0, x1 = 0, y_lo = INFINITY, y_hi = -INFINITY, peak = 0, sum = 0;
    double joint_peak = 0;
    std::string joint_name = "-";
    int n = 0;
    for (const std::vector<double>& row : walk.rows) {
      if (static_cast<int>(row[step]) != k) continue;
      if (n == 0) t0 = row[0], x0 = row[hip_x];
      t1 = row[0], x1 = row[hip_x];
      y_lo = std::min(y_lo, row[hip_y]);
      y_hi = std::max(y_hi, row[hip_y]);
      peak = std::max(peak, std::abs(row[effort]));
      sum += row[effort] * row[effort];
      for (const auto& [c, name] : joints)
        if (const double f = std::hypot(row[c], row[c + 1]); f > joint_peak)
          joint_peak = f, joint_name = name;
      ++n;
    }
    rows.push_back({std::to_string(k), k % 2 ? walk.swing_body : walk.support_body,
                    fixed(walk.support_x[static_cast<size_t>(k)], 5),
                    fixed(t0, 4) + " .. " + fixed(t1, 4), fixed(x0, 5) + " .. " + fixed(x1, 5),
                    fixed(y_lo, 6) + " .. " + fixed(y_hi, 6), fixed(peak, 5),
                    fixed(std::sqrt(sum / std::max(n, 1)), 5),
                    fixed(joint_peak, 5) + " " + joint_name});
  }
  std::cout << table(rows, "  ");
  return 0;
}

}  // namespace

Command walk_command() {
  return {"walk",
          "several steps in the world frame, support foot alternating, start from rest -> CSV",
          kWalkHelp,
          {{"--steps", "", true},
           {"--ramp", "", true},
           {"--samples", "", true},
           {"--mirror", "", true},
           {"--set", "", true, true},
           {"--out", "-o", true}},
          &run_walk};
}

}  // namespace mechgen::cli
