// `mechgen info --json` of a spatial model (DESIGN.md's "Spatial models"): in the library so the
// command line and the Python module give the same text.
#include <sstream>

#include "cli/model_info.hpp"
#include "spatial/spatial_solver.hpp"

namespace mechgen::cli {

namespace {

using spatial::V3;

std::string json_vec(const double* v, int n) {
  std::string out = "[";
  for (int i = 0; i < n; ++i) out += (i ? ", " : "") + number_text(v[i]);
  return out + "]";
}

}  // namespace

std::string spatial_model_info_json(const SpatialModel& model,
                                    const spatial::SpatialSolver& solver) {
  const spatial::SpatialInstance& in = solver.instance();
  const SpatialGraph& g = solver.graph();
  std::ostringstream o;
  o << "{\"name\": " << json_string(model.common.name) << ", \"dimension\": \"spatial\""
    << ", \"gravity\": " << json_vec(in.gravity.data(), 3) << ",\n \"parameters\": {";
  const std::vector<double> values = solver.parameters();
  for (size_t p = 0; p < values.size(); ++p)
    o << (p ? ", " : "") << json_string(model.common.parameters[p].name) << ": "
      << number_text(values[p]);
  o << "},\n \"reference_points\": {";
  bool first = true;
  for (const auto& [point, body] : model.named_points()) {
    const SpatialBody& sb = model.bodies[static_cast<size_t>(body)];
    size_t k = 0;
    while (sb.points[k].name != point) ++k;
    const V3 x = geometry::apply(in.body_frame[static_cast<size_t>(body)],
                                 in.points[static_cast<size_t>(body)][k]);
    o << (first ? "" : ", ") << json_string(point) << ": " << json_vec(x.data(), 3);
    first = false;
  }
  o << "},\n \"bodies\": [";
  first = true;
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    if (model.bodies[b].is_virtual) continue;
    const V3 com = geometry::apply(in.body_frame[b], in.com[b]);
    const std::array<double, 4> q = spatial::quaternion(in.body_frame[b].R);
    o << (first ? "" : ",") << "\n  {\"name\": " << json_string(model.bodies[b].name)
      << ", \"mass\": " << number_text(in.mass[b]) << ", \"com\": " << json_vec(com.data(), 3)
      << ", \"orientation\": " << json_vec(q.data(), 4)
      << ", \"inertia\": " << json_vec(in.inertia[b].m.data(), 9)
      << ", \"ground\": " << (model.bodies[b].ground ? "true" : "false") << "}";
    first = false;
  }
  o << "],\n \"joints\": [";
  first = true;
  for (size_t j = 0; j < model.joints.size(); ++j) {
    const SpatialJoint& joint = model.joints[j];
    if (joint.is_virtual) continue;
    o << (first ? "" : ",") << "\n  {\"name\": " << json_string(joint.name)
      << ", \"type\": " << json_string(to_string(joint.type))
      << ", \"first\": " << json_string(model.bodies[static_cast<size_t>(joint.first)].name)
      << ", \"second\": " << json_string(model.bodies[static_cast<size_t>(joint.second)].name)
      << ", \"point\": "
      << (joint.point.empty() ? json_vec(in.joint_point[j].data(), 3) : json_string(joint.point));
    if (!joint.columns.empty()) {
      const auto& axis = in.axes[static_cast<size_t>(g.joint_column[j])];
      o << ", \"axis\": " << json_vec(axis.s.data(), 3)
        << ", \"pitch\": " << number_text(axis.pitch);
    }
    o << "}";
    first = false;
  }
  o << "],\n \"drivers\": [";
  first = true;
  for (const SpatialDriver& d : model.drivers) {
    o << (first ? "" : ",") << "\n  {\"name\": " << json_string(d.name)
      << ", \"joint\": " << json_string(model.joints[static_cast<size_t>(d.joint)].name)
      << ", \"kind\": " << json_string(to_string(d.kind)) << "}";
    first = false;
  }
  for (const PoseDriver& pd : model.pose_drivers) {
    o << (first ? "" : ",") << "\n  {\"name\": " << json_string(pd.name)
      << ", \"frame\": {\"first\": "
      << json_string(model.bodies[static_cast<size_t>(pd.first)].name)
      << ", \"second\": " << json_string(model.bodies[static_cast<size_t>(pd.second)].name)
      << "}, \"kind\": \"pose\", \"coordinates\": [";
    bool f2 = true;
    for (const PoseCoordinate& c : pd.coordinates)
      if (c.value) o << (f2 ? "" : ", ") << json_string(c.name), f2 = false;
    o << "]}";
    first = false;
  }
  o << "]}\n";
  return o.str();
}

}  // namespace mechgen::cli
