// mechgen import: a URDF (with its Extended URDF closures) or an MJCF file as a spatial
// description (runtime/import/).
#include <cctype>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>

#include "cli/command.hpp"
#include "import/import_tree.hpp"
#include "model/spatial_model.hpp"
#include "report/atomic_output.hpp"
#include "spatial/spatial_solver.hpp"
#include "spatial/spatial_sweep.hpp"

namespace mechgen::cli {

namespace {

const char* const kImportHelp =
    R"(usage: mechgen import FILE.urdf [--closures FILE.yaml] [--floating] -o MODEL.yaml
       mechgen import FILE.xml [--floating] [--springs] -o MODEL.yaml

Writes a spatial description (docs/model_format.md) of a robot written for ROS or MuJoCo:
  FILE.urdf   a URDF tree (urdfdom), with the loop closures of the Extended URDF convention of
              LAAS-CNRS in --closures FILE.yaml: closed_loop (pairs of frames, a link or a joint,
              that must coincide), type (6d: a weld, 3d: a ball), name_mot (the actuated joints),
              joint_name / joint_type (joints re-typed SPHERICAL, UJOINT_AB = about the joint
              frame's x then y, UJOINT_ZY and the like = about those two axes, or FIXED);
  FILE.xml    an MJCF model (MuJoCo's compiler): connect and weld equality constraints as
              closures, actuators on joints as drivers.
The root link is the ground (an MJCF free joint's body too); --floating: the base floats, held
at its source pose by a pose driver (six prescribed coordinates, as models/bioloid.yaml) from a
new ground `world`. Without --closures, a URDF is a tree driven at every joint. Links on fixed joints and the two sides of a weld become one body; a
ball closure a spherical joint at its anchor; three revolutes whose axes meet at a point (through
massless links) a spherical joint, two perpendicular ones a universal joint; a link between two
spherical joints gets a universal joint at one end (its spin about the rod would be idle), a link
between two coaxial revolutes is welded to one neighbour. The loops are closed by Newton-Raphson
from the source's configuration with the actuated joints held (initial and final residual
printed; a loop that cannot close is an error naming the closure and the distance left), and that
assembled pose is the model's reference pose: every coordinate 0 there. Other assemblies at the
same motor positions are looked for from 16 deterministic starts; how many were found is printed
and written in the header (the one reached from the source's configuration is kept). Each
actuated joint is a driver, `amplitude*sin(w*t)` about that pose (parameters amplitude = 0.05
rad, w = 2 pi rad/s). An MJCF joint with stiffness (Cassie's shin and heel springs) is kept
rigid at its spring's rest (springref); --springs keeps it free: a passive driver held at that rest
in sweeps, whose effort under `mechgen simulate` is its spring and damping, -k q - c q' (the
parameters k_JOINT and c_JOINT). The file starts with a comment naming the source and every conversion made. The written model is
then assembled by the numeric solver (as `mechgen check` does) before the command succeeds.

Errors: FILE:LINE: error: MESSAGE, exit code 1.
)";

int run_import(const Args& args) {
  const std::string path = args.single_positional("FILE.urdf or FILE.xml");
  if (!args.has("--out")) throw UsageError("missing -o MODEL.yaml");
  const std::string out = args.get("--out");
  g_current_file = path;
  const std::string ext = std::filesystem::path(path).extension().string();
  try {
    import::Tree tree;
    if (ext == ".urdf") {
      if (args.has("--springs"))
        throw UsageError("--springs is for MJCF files (a URDF joint carries no stiffness)");
      tree = import::read_urdf(path, args.get("--closures"));
    } else if (ext == ".xml" || ext == ".mjcf") {
      if (args.has("--closures")) throw UsageError("--closures is for URDF files");
      tree = import::read_mjcf(path, args.has("--springs"));
    } else {
      throw UsageError("'" + path + "': expected a .urdf or an MJCF .xml file");
    }
    if (tree.name.empty() || tree.name == "onshape" || tree.name == "robot")
      tree.name = std::filesystem::path(out).stem().string();
    if (!tree.name.empty() && std::isdigit(static_cast<unsigned char>(tree.name[0])))
      tree.name = "robot_" + tree.name;
    if (args.has("--floating")) import::float_base(tree);
    import::AssemblyReport report;
    import::TreePose pose = import::assemble(tree, report);
    std::cout << "import " << path << ": " << tree.links.size() << " links, " << tree.joints.size()
              << " joints, " << tree.closures.size() << " closures, " << tree.actuators.size()
              << " actuated\n";
    std::cout << "  loops closed: residual " << report.initial << " -> " << report.final
              << " after " << report.iterations << " Newton steps\n";
    std::ostringstream closed;
    closed.precision(3);
    closed << "loops closed from the source's configuration: residual " << report.initial << " -> "
           << report.final << " (m, rad) in " << report.iterations << " Newton steps"
           << (report.restarts ? " (trapped there: restarted from other configurations, the "
                                 "assembly nearest the source's kept)"
                               : "");
    if (report.others > 0) {
      std::ostringstream other;
      other.precision(3);
      other << report.others << " other assembl" << (report.others == 1 ? "y" : "ies")
            << " at these motor positions (found from " << report.starts
            << " deterministic starts; the nearest " << report.other_distance
            << " from the source's coordinates): kept the one reached from the source's "
               "configuration ("
            << report.kept_distance << " from them)";
      std::cout << "  " << other.str() << "\n";
      closed << "; " << other.str();
    }
    tree.notes.push_back(closed.str());
    import::hold_free_joints(tree, pose);
    const import::Description d = import::describe(tree, pose, args.has("--floating"));
    const std::string text = import::write_model(d);
    report::write_file_atomically(out, text);
    std::cout << "  " << d.bodies.size() << " bodies, " << d.joints.size() << " joints, "
              << d.drivers.size() << " drivers -> " << out << "\n";
    // The written model as every command reads it: assembled by the numeric solver at t0.
    g_current_file = out;
    const SpatialModel model = read_spatial_model(out);
    const spatial::SpatialSolver solver(model, {});
    spatial::SpatialState state;
    solver.solve(spatial::default_spatial_sweep(model).t0, state);
    std::cout << "  " << out << ": assembles (" << state.q.size() << " coordinates)\n";
  } catch (const import::ImportError& error) {
    std::cerr << error.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

Command import_command() {
  return {"import",
          "a URDF (+ Extended URDF closures) or MJCF robot as a spatial description",
          kImportHelp,
          {{"--out", "-o", true},
           {"--closures", "", true},
           {"--floating", "", false},
           {"--springs", "", false}},
          &run_import};
}

}  // namespace mechgen::cli
