#include "analysis/walking.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <tuple>
#include <utility>

#include "model/columns.hpp"
#include "sweep/compiled_kernel.hpp"
#include "sweep/sweep.hpp"

namespace mechgen::analysis {

namespace {

std::string format_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

// Index of the body or point named name + suffix, or of the one name is the mirror of; -1: none.
template <class Find>
int mirror_of(const std::string& name, const std::string& suffix, Find find) {
  if (const int mirror = find(name + suffix); mirror >= 0) return mirror;
  if (name.size() > suffix.size() && name.ends_with(suffix))
    return find(name.substr(0, name.size() - suffix.size()));
  return -1;
}

// The driver's advance since the start, a(t) = q(t) - q0, and its inverse.
struct Schedule {
  double speed = 0, ramp = 0;
  double advance(double t) const { return ramped_motion(0, speed, ramp, t).q; }
  double time_at(double a) const {
    const double ramp_advance = speed * ramp / 2;
    if (a >= ramp_advance) return ramp + (a - ramp_advance) / speed;
    double lo = 0, hi = ramp;  // a(t) increases strictly on (0, ramp]
    for (int i = 0; i < 200 && hi - lo > 1e-15 * ramp; ++i) {
      const double mid = (lo + hi) / 2;
      (advance(mid) < a ? lo : hi) = mid;
    }
    return (lo + hi) / 2;
  }
};

}  // namespace

DriverMotion ramped_motion(double q0, double speed, double ramp_time, double t) {
  if (ramp_time <= 0) return {q0 + speed * t, speed, 0};
  if (t >= ramp_time) return {q0 + speed * (t - ramp_time / 2), speed, 0};
  if (t <= 0) return {q0, 0, 0};
  const double u = t / ramp_time;
  const double u2 = u * u, u3 = u2 * u;
  const double s = u3 * (10 - 15 * u + 6 * u2);
  const double integral = u2 * u2 * (2.5 - 3 * u + u2);
  return {q0 + speed * ramp_time * integral, speed * s,
          speed / ramp_time * 30 * u2 * (1 - u) * (1 - u)};
}

int WalkResult::column(const std::string& name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : static_cast<int>(it - columns.begin());
}

WalkResult walk(const Model& model, const WalkOptions& options) {
  const SourceLoc where{model.file, 0, 0};
  if (options.steps < 1) throw ModelError(where, "walk: --steps must be at least 1");
  if (!(options.ramp >= 0) || !std::isfinite(options.ramp))
    throw ModelError(where, "walk: the ramp time must be a finite number >= 0");
  if (options.samples_per_step != 0 && options.samples_per_step < 2)
    throw ModelError(where, "walk: at least 2 samples per step");
  if (model.drivers.size() != 1)
    throw ModelError(where, "walk: needs exactly one driver (the motor); '" + model.name +
                                "' has " + std::to_string(model.drivers.size()));
  const Driver& driver = model.drivers.front();
  // The walk is one table in memory (a huge --steps grew it without bound): checked up front.
  check_table_memory(model,
                     static_cast<size_t>(options.steps) *
                         static_cast<size_t>(options.samples_per_step > 0 ? options.samples_per_step
                                                                          : model.step.samples),
                     column_names(model).size());

  // The model's own motion at both ends of its step, through the generated kernel: this also
  // checks that the compiled kernel matches the description.
  SweepOptions ends = default_sweep(model, options.parameters);
  ends.samples = 2;
  const SweepResult own = run_sweep(model, ends);
  const ColumnLayout layout = column_layout(model);
  const int dcol = layout.driver.front();
  const double q0 = own.rows[0][static_cast<size_t>(dcol)];
  const double speed = own.rows[0][static_cast<size_t>(dcol + 1)];
  const double step_time = ends.t1 - ends.t0;
  if (!(speed > 0) || own.rows[0][static_cast<size_t>(dcol + 2)] != 0 ||
      std::abs(own.rows[1][static_cast<size_t>(dcol + 1)] - speed) > 1e-12 * speed ||
      !(step_time > 0))
    throw ModelError(driver.loc, "walk: driver '" + driver.name +
                                     "' must run at a constant positive speed over the model's "
                                     "step (t0 < t1), as one support phase does");
  const double step_angle = speed * step_time;

  // Mirrors: the flying leg's bodies and points.
  const std::string& suffix = options.mirror_suffix;
  const auto points = model.named_points();
  auto find_point = [&](const std::string& name) {
    for (size_t i = 0; i < points.size(); ++i)
      if (points[i].first == name) return static_cast<int>(i);
    return -1;
  };
  std::vector<int> body_mirror, point_mirror;
  for (const Body& body : model.bodies)
    body_mirror.push_back(
        mirror_of(body.name, suffix, [&](const std::string& n) { return model.body_index(n); }));
  for (const auto& [name, body] : points)
    point_mirror.push_back(mirror_of(name, suffix, find_point));
  // A joint's mirror joins its bodies' mirrors at its point's mirror; listed the other way round
  // (second, first), its force is the opposite.
  auto mirrored_body = [&](int b) {
    return body_mirror[static_cast<size_t>(b)] >= 0 ? body_mirror[static_cast<size_t>(b)] : b;
  };
  std::vector<std::pair<int, double>> joint_mirror;  // (joint, sign)
  for (const Joint& j : model.joints) {
    const int point = find_point(j.point);
    const int mirror_point = point >= 0 ? point_mirror[static_cast<size_t>(point)] : -1;
    const std::string& at =
        mirror_point >= 0 ? points[static_cast<size_t>(mirror_point)].first : j.point;
    const int first = mirrored_body(j.first), second = mirrored_body(j.second);
    std::pair<int, double> found{-1, 0.0};
    for (size_t m = 0; m < model.joints.size(); ++m) {
      const Joint& c = model.joints[m];
      if (c.point != at || c.type != j.type) continue;
      if (c.first == first && c.second == second) found = {static_cast<int>(m), 1.0};
      if (c.first == second && c.second == first) found = {static_cast<int>(m), -1.0};
    }
    if (found.first < 0)
      throw ModelError(j.loc, "walk: joint '" + j.name + "' has no mirror joint between '" +
                                  model.bodies[static_cast<size_t>(first)].name + "' and '" +
                                  model.bodies[static_cast<size_t>(second)].name + "' at '" + at +
                                  "'");
    joint_mirror.push_back(found);
  }
  const Body& ground = model.bodies[static_cast<size_t>(model.ground)];
  const int swing = body_mirror[static_cast<size_t>(model.ground)];
  if (swing < 0)
    throw ModelError(ground.loc, "walk: the ground body '" + ground.name +
                                     "' (the support foot) has no mirror '" + ground.name + suffix +
                                     "' (the other foot)");
  if (ground.points.empty() || find_point(ground.points.front().name) < 0 ||
      point_mirror[static_cast<size_t>(find_point(ground.points.front().name))] < 0)
    throw ModelError(ground.loc, "walk: the ground body's first point has no mirror point on '" +
                                     model.bodies[static_cast<size_t>(swing)].name + "'");
  const int foot_point = find_point(ground.points.front().name);
  const int landing_point = point_mirror[static_cast<size_t>(foot_point)];
  const int crank = model.joints[static_cast<size_t>(driver.joint)].second;
  const bool turn_crank =
      driver.kind == DriverKind::angle && body_mirror[static_cast<size_t>(crank)] < 0;

  // The ground body's reported centre: its centre of mass, or its points' centroid if massless.
  const GiNaC::exmap subs = model.substitutions(ends.parameters);
  double ground_cx = 0, ground_cy = 0;
  if (ground.mass.source != MassProperties::Source::none) {
    ground_cx = model.evaluate(ground.mass.com.x, subs);
    ground_cy = model.evaluate(ground.mass.com.y, subs);
  } else {
    for (const BodyPoint& p : ground.points) {
      ground_cx += model.evaluate(p.local.x, subs) / static_cast<double>(ground.points.size());
      ground_cy += model.evaluate(p.local.y, subs) / static_cast<double>(ground.points.size());
    }
  }

  const CompiledKernel& kernel = generated_kernel(model);
  std::vector<double> kernel_row(static_cast<size_t>(kernel.column_count));
  auto evaluate = [&](double t, const DriverMotion& m) {
    const double drivers[3] = {m.q, m.qd, m.qdd};
    int group = -1;
    const int status = kernel.evaluate_driven_double(ends.parameters.data(), ends.t0 + t, drivers,
                                                     kernel_row.data(), &group);
    if (status != 0) {
      std::string message = "walk: generated kernel: t = " + format_number(t) + ", " + driver.name +
                            " = " + format_number(m.q) + ": " +
                            (status == 1   ? "unreachable"
                             : status == 2 ? "singular"
                                           : "non-finite result");
      if (group >= 0 && group < kernel.group_count)
        message += " in group " + std::string(kernel.group_names[group]);
      throw ModelError(where, message);
    }
  };

  // Stride: where the landing foot's point stands at the end of a step, relative to the support
  // foot's same point (the kernel's positions depend on q only).
  evaluate(step_time, {q0 + step_angle, speed, 0});
  const double stride =
      kernel_row[static_cast<size_t>(layout.point[static_cast<size_t>(landing_point)])] -
      own.rows[0][static_cast<size_t>(layout.point[static_cast<size_t>(foot_point)])];

  WalkResult result;
  result.support_body = ground.name;
  result.swing_body = model.bodies[static_cast<size_t>(swing)].name;
  result.hip_body =
      model.bodies[static_cast<size_t>(model.joints[static_cast<size_t>(driver.joint)].first)].name;
  result.step_angle = step_angle;
  result.speed = speed;
  result.step_time = step_time;
  for (int k = 0; k < options.steps; ++k) result.support_x.push_back(k * stride);
  result.columns = {"t", "step", "support", "support.x"};
  for (const char* c : {".q", ".qd", ".qdd", ".effort"}) result.columns.push_back(driver.name + c);
  for (const Body& body : model.bodies)
    for (const char* c : {".x", ".y", ".th", ".vx", ".vy", ".w", ".ax", ".ay", ".al"})
      result.columns.push_back(body.name + c);
  for (const auto& [name, body] : points) {
    result.columns.push_back(name + ".x");
    result.columns.push_back(name + ".y");
  }
  for (const Joint& j : model.joints) {
    result.columns.push_back(j.name + ".fx");
    result.columns.push_back(j.name + ".fy");
    if (j.type == JointType::prismatic) result.columns.push_back(j.name + ".m");
  }

  // Sample times: uniform at the model's resolution, plus every support change twice.
  const int per_step = options.samples_per_step > 0 ? options.samples_per_step : model.step.samples;
  const double dt = step_time / std::max(1, per_step - 1);
  const Schedule schedule{speed, options.ramp};
  const double t_end = schedule.time_at(options.steps * step_angle);
  std::vector<std::tuple<double, int, bool>> samples;  // t, step, on a step boundary
  for (int k = 0; k <= options.steps; ++k) {
    const double tk = k == 0 ? 0.0 : schedule.time_at(k * step_angle);
    if (k > 0) samples.emplace_back(tk, k - 1, true);
    if (k < options.steps) samples.emplace_back(tk, k, true);
  }
  for (long i = 1;; ++i) {
    const double t = static_cast<double>(i) * dt;
    if (t >= t_end - 1e-9 * dt) break;
    const int k = std::clamp(static_cast<int>(std::floor(schedule.advance(t) / step_angle)), 0,
                             options.steps - 1);
    if (std::abs(schedule.time_at((k + 1) * step_angle) - t) < 1e-9 * dt ||
        (k > 0 && std::abs(schedule.time_at(k * step_angle) - t) < 1e-9 * dt))
      continue;  // on a support change: already there twice
    samples.emplace_back(t, k, false);
  }
  std::sort(samples.begin(), samples.end());

  for (const auto& [t, k, boundary] : samples) {
    const DriverMotion motion = ramped_motion(q0, speed, options.ramp, t);
    // The driver's advance within step k; exact at the step's ends.
    double local = motion.q - q0 - k * step_angle;
    if (boundary) local = std::abs(local) < std::abs(local - step_angle) ? 0.0 : step_angle;
    evaluate(t, {q0 + local, motion.qd, motion.qdd});
    const bool swapped = k % 2 == 1;
    const double offset = result.support_x[static_cast<size_t>(k)];
    std::vector<double> row{t,
                            static_cast<double>(k),
                            swapped ? 1.0 : 0.0,
                            offset,
                            motion.q,
                            motion.qd,
                            motion.qdd,
                            kernel_row[static_cast<size_t>(dcol + 3)]};
    for (size_t b = 0; b < model.bodies.size(); ++b) {
      const int source = swapped && body_mirror[b] >= 0 ? body_mirror[b] : static_cast<int>(b);
      if (source == model.ground) {
        row.insert(row.end(), {ground_cx + offset, ground_cy, 0, 0, 0, 0, 0, 0, 0});
        continue;
      }
      const size_t c = static_cast<size_t>(layout.body[static_cast<size_t>(source)]);
      row.insert(row.end(), kernel_row.begin() + static_cast<long>(c),
                 kernel_row.begin() + static_cast<long>(c + 9));
      row[row.size() - 9] += offset;
      if (turn_crank && static_cast<int>(b) == crank)
        row[row.size() - 7] =
            std::remainder(row[row.size() - 7] + k * step_angle, 2 * std::numbers::pi);
    }
    for (size_t p = 0; p < points.size(); ++p) {
      const int source = swapped && point_mirror[p] >= 0 ? point_mirror[p] : static_cast<int>(p);
      const size_t c = static_cast<size_t>(layout.point[static_cast<size_t>(source)]);
      row.push_back(kernel_row[c] + offset);
      row.push_back(kernel_row[c + 1]);
    }
    for (size_t j = 0; j < model.joints.size(); ++j) {
      const auto [source, sign] =
          swapped ? joint_mirror[j] : std::pair<int, double>{static_cast<int>(j), 1.0};
      const size_t c = static_cast<size_t>(layout.joint[static_cast<size_t>(source)]);
      const size_t width = model.joints[j].type == JointType::prismatic ? 3 : 2;
      for (size_t i = 0; i < width; ++i) row.push_back(sign * kernel_row[c + i]);
    }
    result.rows.push_back(std::move(row));
  }
  return result;
}

}  // namespace mechgen::analysis
