// mechgen export: a spatial model as URDF with Extended URDF closures, or as MJCF
// (runtime/import/model_export.hpp).
#include <filesystem>
#include <iostream>
#include <string>

#include "cli/command.hpp"
#include "import/model_export.hpp"
#include "model/spatial_model.hpp"
#include "report/atomic_output.hpp"

namespace mechgen::cli {

namespace {

const char* const kExportHelp =
    R"(usage: mechgen export MODEL.yaml --urdf OUT.urdf [--closures OUT.yaml]
       mechgen export MODEL.yaml --mjcf OUT.xml

Writes a spatial model (at its default parameters, in its reference pose) for ROS, Pinocchio or
MuJoCo users. The joint graph's spanning tree is the URDF (MJCF) tree: universal and spherical
joints in it become two or three revolutes through massless links (MJCF: hinges in one body, a
ball), a body's URDF link frame lies on the axis of the joint above it. Each chord closes a loop:
a spherical chord is a ball closure at its point (Extended URDF `3d`, MJCF `connect`), any other
chord is kept as a joint to a massless cut link welded to its second body (`6d`, MJCF `weld`).
--closures (default: OUT.urdf with the extension .yaml) gets closed_loop, type and name_mot (the
driven joints), and mechgen's additions: gravity, driver_values (each driver's law, default
parameters substituted), driver_names, step (MJCF: <custom> texts mechgen_value_<actuator> and
mechgen_step). Named points are frame links (URDF) or sites (MJCF). `mechgen import` reads both
back: the round trip sweeps as the model does.
Pose drivers and helical joints have no URDF or MJCF form (an error at the element).
)";

int run_export(const Args& args) {
  const std::string path = args.single_positional("MODEL.yaml");
  g_current_file = path;
  if (args.has("--urdf") == args.has("--mjcf"))
    throw UsageError("give --urdf OUT.urdf or --mjcf OUT.xml");
  if (!is_spatial_description(path))
    throw UsageError("'" + path + "' is not a spatial description (dimension: spatial)");
  const SpatialModel model = read_spatial_model(path);
  if (args.has("--urdf")) {
    const std::string urdf = args.get("--urdf");
    const std::string closures =
        args.get("--closures", std::filesystem::path(urdf).replace_extension(".yaml").string());
    report::check_output_path(urdf);
    report::check_output_path(closures);
    const import::UrdfExport out = import::export_urdf(model, path);
    report::write_file_atomically(urdf, out.urdf);
    report::write_file_atomically(closures, out.closures);
    std::cout << "export " << path << " -> " << urdf << ", " << closures << "\n";
  } else {
    const std::string mjcf = args.get("--mjcf");
    report::check_output_path(mjcf);
    report::write_file_atomically(mjcf, import::export_mjcf(model, path));
    std::cout << "export " << path << " -> " << mjcf << "\n";
  }
  return 0;
}

}  // namespace

Command export_command() {
  return {"export",
          "a spatial model as URDF (+ Extended URDF closures) or MJCF",
          kExportHelp,
          {{"--urdf", "", true}, {"--mjcf", "", true}, {"--closures", "", true}},
          &run_export};
}

}  // namespace mechgen::cli
