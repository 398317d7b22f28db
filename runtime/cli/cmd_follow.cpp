// mechgen follow: a twin with joint drivers (the actuators) along a pose-driven spatial model's
// motion -> the actuators' coordinates, rates, accelerations and efforts over the step (CSV).
#include <iostream>
#include <string>

#include "analysis/follow.hpp"
#include "cli/command.hpp"
#include "cli/model_info.hpp"
#include "model/spatial_value_checks.hpp"
#include "report/csv_table.hpp"

namespace mechgen::cli {

namespace {

const char* const kFollowHelp =
    R"(usage: mechgen follow DRIVEN.yaml --twin TWIN.yaml --out FILE.csv [--samples N]
                      [--set NAME=VALUE]...

DRIVEN is a spatial model driven by a pose driver (inverse kinematics: a foot on a trajectory);
TWIN has the same joints with joint drivers on the actuated ones (the cylinders). Over DRIVEN's
step, each sample is solved exactly (positions, velocities, accelerations), each TWIN driver's
joint coordinate and its rates are read from it, TWIN is solved there and its Newton-Euler gives
the actuator efforts. Numeric reference solver for both.
  --twin TWIN.yaml  the actuated twin
  --out FILE.csv    t, then per TWIN driver: .q .qd .qdd (its joint coordinate, from the
                    reference pose) and .effort (force or torque of the actuator)
  --samples N       samples over DRIVEN's step (default 201)
  --set NAME=VALUE  overrides DRIVEN's parameters (TWIN keeps its defaults)
)";

int run_follow_command(const Args& args) {
  const std::string path = args.single_positional("DRIVEN.yaml");
  if (!args.has("--twin")) throw UsageError("missing --twin TWIN.yaml");
  if (!args.has("--out")) throw UsageError("missing --out FILE.csv");
  g_current_file = path;
  const SpatialModel driven = read_spatial_model(path);
  g_current_file = args.get("--twin");
  const SpatialModel twin = read_spatial_model(args.get("--twin"));
  analysis::FollowOptions o;
  o.parameters = driven.common.default_parameters();
  apply_overrides(driven, args.all("--set"), o.parameters);
  o.samples = static_cast<int>(args.integer("--samples", 201));
  if (o.samples < 1) throw UsageError("--samples must be at least 1");
  const analysis::FollowResult r = analysis::follow(driven, twin, o);
  const std::string out = args.get("--out");
  g_current_file = out;
  report::write_csv(report::CsvTable{out, r.columns, r.rows}, out);
  std::cout << "follow " << twin.common.name << " along " << driven.common.name << ": "
            << r.rows.size() << " samples -> " << out << "\n";
  return 0;
}

}  // namespace

Command follow_command() {
  return {"follow",
          "actuated twin along a pose-driven spatial model's motion -> CSV",
          kFollowHelp,
          {{"--twin", "", true},
           {"--out", "-o", true},
           {"--samples", "", true},
           {"--set", "", true, true}},
          &run_follow_command};
}

}  // namespace mechgen::cli
