// mechgen draw: the mechanism as an SVG drawing, at one time or animated over a step or a walk.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>

#include "analysis/walking.hpp"
#include "cli/cmd_spatial.hpp"
#include "cli/command.hpp"
#include "report/atomic_output.hpp"
#include "report/mechanism_drawing.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::cli {

namespace {

const char* const kDrawHelp =
    R"(usage: mechgen draw MODEL.yaml (--at T | --animate [--steps N [--ramp SECONDS]])
                    [--set NAME=VALUE]... [--solver generated|numeric] [--labels]
                    [--trace POINT[,POINT...]]... [--title TEXT] [--width PIXELS] --out FILE.svg

Draws the mechanism: bodies as bars or plates between their points, joints as circles, the
ground body on a hatched floor (model ground frame). A spatial model (dimension: spatial) is drawn
by the numeric solver in two orthographic views side by side, chosen from its extent: sagittal
(x-z) and frontal (y-z) unless one is edge-on, then top (x-y); one view alone when it lies in a
plane; the figure says which views it left out.
  --at T              a still at time T (s)
  --animate           an animated SVG (SMIL, looping in real time) of the model's step; its
                      first frame is the still at the step's start
  --steps N           with --animate: N steps of walking in the world frame, the support foot
                      alternating (as mechgen walk; generated kernel only)
  --ramp SECONDS      with --steps: start from rest with this motor-speed ramp
  --solver NAME       generated (default) or numeric, for --at and a one-step --animate
  --labels            body names beside the bodies
  --trace POINTS      the paths of these named points (comma separated, repeatable), dashed:
                      over the model's step on a still, over the animation on --animate (a dot
                      follows each point)
  --title TEXT        a title, followed by what is drawn, e.g. (t = 0.5 s), (one step, 1.2 s)
                      or (6 steps walking, world frame)
  --width PIXELS      drawing width (default 900)
)";

int run_draw(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  if (is_spatial_description(path)) return run_spatial_draw(args);
  if (!args.has("--out")) throw UsageError("missing --out FILE.svg");
  if (args.has("--at") == args.has("--animate"))
    throw UsageError("give either --at T or --animate");
  if (args.has("--steps") && !args.has("--animate")) throw UsageError("--steps needs --animate");
  if (args.has("--ramp") && !args.has("--steps")) throw UsageError("--ramp needs --steps");
  const std::string solver = solver_option(args);
  if (args.has("--steps") && solver != "generated")
    throw UsageError("--steps walks with the generated kernel only");
  report::DrawingOptions drawing;
  drawing.labels = args.has("--labels");
  drawing.title = args.get("--title");
  drawing.width = args.integer("--width", 900);
  if (drawing.width < 100) throw UsageError("--width must be at least 100");
  const Model model = load_model(path);
  std::vector<double> parameters = model.default_parameters();
  apply_overrides(model, args.all("--set"), parameters);
  drawing.trace = comma_list(args, "--trace");

  report::MechanismFrames frames;
  std::string what;
  if (args.has("--steps")) {
    analysis::WalkOptions walk;
    walk.parameters = parameters;
    walk.steps = args.integer("--steps", 1);
    if (walk.steps < 1) throw UsageError("--steps must be at least 1");
    walk.ramp = args.number("--ramp", 0);
    if (walk.ramp < 0) throw UsageError("--ramp must be at least 0");
    const analysis::WalkResult result = analysis::walk(model, walk);
    frames = report::frames_from_table(model, result.columns, result.rows);
    what = std::to_string(walk.steps) + " steps walking, world frame";
  } else {
    SweepOptions sweep = default_sweep(model, parameters);
    sweep.solver = solver;
    if (args.has("--at")) {
      const double at = args.number("--at", 0);
      // The numeric solver continues from the model's t0, where its assembly hints hold.
      if (solver == "numeric") {
        sweep.samples = std::max(
            2, static_cast<int>(std::abs(at - sweep.t0) / std::max(1e-9, sweep.t1 - sweep.t0) *
                                (sweep.samples - 1)) +
                   2);
        sweep.t1 = at;
      } else {
        sweep.t0 = sweep.t1 = at;
        sweep.samples = 1;
      }
      SweepResult result = run_sweep(model, sweep);
      result.rows.erase(result.rows.begin(), result.rows.end() - 1);
      frames = report::frames_from_table(model, result.columns, result.rows);
      what = "t = " + fixed(at, 6) + " s";
      if (!drawing.trace.empty()) {  // the traced paths: over the model's step
        SweepOptions step = default_sweep(model, parameters);
        step.solver = solver;
        const SweepResult whole = run_sweep(model, step);
        drawing.trace_path = report::frames_from_table(model, whole.columns, whole.rows);
      }
    } else {
      const SweepResult result = run_sweep(model, sweep);
      frames = report::frames_from_table(model, result.columns, result.rows);
      what = "one step, " + fixed(sweep.t1 - sweep.t0, 4) + " s";
    }
  }
  // The title says what was drawn, so it cannot claim another run ("4 steps" over 6).
  if (!drawing.title.empty()) drawing.title += " (" + what + ")";
  const std::string out = args.get("--out");
  g_current_file = out;
  report::write_file_atomically(out, report::draw_mechanism(model, frames, drawing));
  std::cout << "draw " << model.name << ": " << what << ", " << frames.points.size()
            << " frames -> " << out << "\n";
  return 0;
}

}  // namespace

Command draw_command() {
  return {"draw",
          "SVG drawing of the mechanism at a time, or animated over a step or a walk",
          kDrawHelp,
          {{"--at", "", true},
           {"--animate", "", false},
           {"--steps", "", true},
           {"--ramp", "", true},
           {"--solver", "", true},
           {"--labels", "", false},
           {"--trace", "", true, true},
           {"--title", "", true},
           {"--width", "", true},
           {"--set", "", true, true},
           {"--out", "-o", true}},
          &run_draw};
}

}  // namespace mechgen::cli
