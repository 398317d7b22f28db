// What `mechgen view` shows, planar or spatial alike: bodies as rigid groups of shapes in their own
// frame, each frame's pose straight from a sweep table (centre of mass and orientation, never
// recomputed by the viewer), named points, traced paths and plotted columns. The HTML page
// (html_view.hpp) and the glTF file (gltf_export.hpp) are both written from this.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace mechgen::report {

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>;  // w, x, y, z

// One solid or line of a body, in the body's tracked frame (origin at its centre of mass).
struct ViewShape {
  enum class Kind { cylinder, box, plate, sphere, line };
  enum class Role { link, joint, ground };
  Kind kind = Kind::line;
  Role role = Role::link;
  Vec3 a{}, b{};              // cylinder: axis ends; line: polyline in `outline`
  double radius = 0;          // cylinder, sphere
  Vec3 center{};              // box, sphere
  Vec3 size{};                // box edge lengths along its own axes
  Quat rotation{1, 0, 0, 0};  // box: its axes in the body frame
  std::vector<Vec3> outline;  // plate: polygon in a plane z = const; line: the polyline
  double thickness = 0;       // plate: along z, centred on the outline's plane
  bool inertia_box = false;   // a box standing for an explicit mass (drawn translucent)
};

struct ViewBody {
  std::string name;
  bool ground = false;
  std::vector<ViewShape> shapes;
  // Per frame: the tracked frame's origin and orientation (a sweep's B.x, B.y[, B.z] and B.th or
  // B.qw..qz). A body without columns (the ground of a sweep) has one pose for every frame.
  std::vector<Vec3> position;
  std::vector<Quat> orientation;
};

struct ViewLabel {  // a named point or a joint, carried by a body
  std::string name;
  int body = -1;
  Vec3 local{};
};

struct ViewSeries {
  std::string name;
  std::vector<double> values;  // per frame
};

struct ViewScene {
  std::string title;
  std::string dimension;  // "planar" or "spatial"
  Vec3 up{0, 0, 1};       // against gravity
  double size = 1;        // the mechanism's extent (m): sets the markers and the frame's axes
  std::vector<double> times;
  std::vector<ViewBody> bodies;
  std::vector<ViewLabel> points, joints;
  std::vector<std::pair<std::string, std::vector<Vec3>>> traces;  // per frame positions
  std::vector<ViewSeries> plot;
  std::string plot_note;  // e.g. "first 8 of 24 torques; --plot to choose"
};

// A planar body angle as the quaternion of a rotation about z.
Quat planar_rotation(double th);

}  // namespace mechgen::report
