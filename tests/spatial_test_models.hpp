// Spatial test mechanisms shared by the kinematics and dynamics suites: the shipped closed chains,
// leg6 as inverse kinematics (its foot pose-driven) and a helical-spherical-universal-cylindrical
// loop that exercises the remaining joint types.
#pragma once

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace mechgen::spatial {

inline std::string text_of(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// `copies` RSUR loops (models/rsur.yaml) side by side 0.3 m apart along x, sharing only the ground,
// one crank driver each at w*t, shifted by 2 pi i / copies when `out_of_phase`.
inline std::string rsur_copies(int copies, bool out_of_phase) {
  const std::string rsur = text_of(MECHGEN_SOURCE_DIR "/models/rsur.yaml");
  std::string ground, moving, joints, drivers;
  for (int i = 0; i < copies; ++i) {
    const std::string k = std::to_string(i), x = std::to_string(0.3 * i);
    const std::string bar = "], radius: r, density: rho}}\n";
    ground += (i ? ", " : "") + std::string("A") + k + ": [" + x + ", 0, 0], D" + k + ": [" + x +
              ", d, h]";
    moving += "  - {name: crank" + k + ", points: {A" + k + ": [" + x + ", 0, 0], B" + k + ": [" +
              x + " + a, 0, 0]}, mass: {bar: [A" + k + ", B" + k + bar + "  - {name: coupler" + k +
              ", points: {B" + k + ": [" + x + " + a, 0, 0], C" + k + ": [" + x +
              ", d, h + c]}, mass: {bar: [B" + k + ", C" + k + bar + "  - {name: rocker" + k +
              ", points: {D" + k + ": [" + x + ", d, h], C" + k + ": [" + x +
              ", d, h + c]}, mass: {bar: [D" + k + ", C" + k + bar;
    joints += "  - {name: jA" + k + ", type: revolute, first: ground, second: crank" + k +
              ", s: [0, 0, 1], s0: A" + k + "}\n  - {name: jB" + k +
              ", type: spherical, first: crank" + k + ", second: coupler" + k + ", s0: B" + k +
              "}\n  - {name: jC" + k + ", type: universal, first: coupler" + k +
              ", second: rocker" + k + ", s: [1, 0, 0], s2: [0, 0, 1], s0: C" + k +
              "}\n  - {name: jD" + k + ", type: revolute, first: ground, second: rocker" + k +
              ", s: [1, 0, 0], s0: D" + k + "}\n";
    drivers += "  - {name: theta" + k + ", joint: jA" + k + ", kind: angle, value: w*t" +
               (out_of_phase && i ? " + 2*pi*" + k + "/" + std::to_string(copies) : "") + "}\n";
  }
  return rsur.substr(0, rsur.find("bodies:")) +
         "bodies:\n  - {name: ground, ground: true, points: {" + ground + "}}\n" + moving +
         "joints:\n" + joints + "drivers:\n" + drivers +
         "step: {t0: 0, t1: 2*pi/w, samples: 181}\n";
}

// leg6 as inverse kinematics: the same leg, its foot pose-driven relative to the waist.
inline std::string leg6_inverse_kinematics() {
  std::string text = text_of(MECHGEN_SOURCE_DIR "/models/leg6.yaml");
  text = text.substr(0, text.find("drivers:"));
  const auto hint = [&](const std::string& joint, const std::string& value) {
    const auto at = text.find("{name: " + joint + ",");
    text.insert(at + 1, "assembly: " + value + ", ");
  };
  hint("hip_pitch", "-0.4");
  hint("knee", "0.8");
  hint("ankle_pitch", "-0.4");
  return text +
         "drivers:\n  - {name: foot_pose, type: pose, first: waist, second: foot_link, at: foot,\n"
         "     x: 0.02*sin(w*t), y: 0.01*sin(w*t), z: -0.16 + 0.01*cos(w*t),\n"
         "     rotations: [{axis: z, value: 0.1*sin(w*t)}, {axis: y, value: 0.05*sin(2*w*t)},\n"
         "                 {axis: x, value: -0.05*sin(w*t)}]}\n"
         "step: {t0: 0, t1: 2*pi/w, samples: 41}\n";
}

struct Case {
  std::string name, text;
};
// H-S-U-C loop: a crank screwed along z by a helical joint (pitch 10 mm/rad), a rod with a
// spherical joint at the crank tip and a universal joint at a slider that slides along and turns
// about a line parallel to x (cylindrical). 1 + 3 + 2 + 2 = 8 coordinates, two drivers (the
// screw angle and the slider's turn), N_s 6 x 6; a force on the slider and a couple on the crank.
inline const char* const kHsucLoop = R"(name: hsuc
dimension: spatial
gravity: [0, 0, -9.81]
parameters: {w: 2}
bodies:
  - {name: ground, ground: true, points: {O: [0, 0, 0], L: [0, 0.05, 0.02]}}
  - {name: crank, points: {O: [0, 0, 0], B: [0.04, 0, 0]}, mass: {bar: [O, B], radius: 0.005, density: 7800}}
  - {name: rod, points: {B: [0.04, 0, 0], C: [0.15, 0.05, 0.02]}, mass: {bar: [B, C], radius: 0.004, density: 2700}}
  - {name: slider, points: {C: [0.15, 0.05, 0.02], E: [0.15, 0.08, 0.02]},
     mass: {mass: 0.2, com: [0.15, 0.06, 0.02], inertia: [[2e-5, 1e-6, 0], [1e-6, 3e-5, 2e-6], [0, 2e-6, 2.5e-5]]}}
joints:
  - {name: screw, type: helical, first: ground, second: crank, s: [0, 0, 1], s0: O, pitch: 0.01}
  - {name: ball, type: spherical, first: crank, second: rod, s0: B}
  - {name: cross, type: universal, first: rod, second: slider, s: [0, 1, 0], s2: [0, 0, 1], s0: C}
  - {name: sleeve, type: cylindrical, first: ground, second: slider, s: [1, 0, 0], s0: L}
drivers:
  - {name: turn, joint: screw, kind: angle, value: w*t}
  - {name: twist, joint: sleeve, kind: angle, value: 0.3*sin(w*t)}
forces:
  - {name: load, type: force, body: slider, point: E, value: [-5*cos(w*t), 2, 1 + t]}
  - {name: drag, type: torque, body: crank, value: [0.01, 0, -0.05*sin(w*t)]}
step: {t0: 0, t1: pi/w, samples: 31}
)";

// The seed 001 humanoid's structure: a waist and four 6-DOF limbs (Table 1 axes; knees and elbows
// offset 20 mm forward so no limb is straight), the waist and each limb's end pose-driven from
// the ground by five 3P3R virtual chains. The waist sways and yaws, the right foot steps, the
// other ends stay put: 4 circuits, N 24 x 54, 30 primary virtual joints.
inline std::string humanoid() {
  std::string text =
      "name: humanoid\ndimension: spatial\nbodies:\n  - {name: ground, ground: true}\n"
      "  - {name: waist, mass: {mass: 1, com: [0, 0, 0.3], inertia: [0.01, 0.01, 0.01]}}\n";
  std::string
      joints = "joints:\n",
      drivers =
          "drivers:\n  - {name: waist_pose, type: pose, first: "
          "ground, second: waist, at: [0, 0, 0.3], x: 0.005*sin(2*t), y: 0, z: "
          "0.3 - 0.005*sin(2*t), rotations: [{axis: z, value: 0.05*sin(2*t)}, {axis: y, value: "
          "0}, {axis: x, value: 0}]}\n";
  const char* limbs[4] = {"rleg", "lleg", "rarm", "larm"};
  const char* axes[6] = {"[0, 0, 1]", "[1, 0, 0]", "[0, 1, 0]",
                         "[0, 1, 0]", "[0, 1, 0]", "[1, 0, 0]"};
  for (int l = 0; l < 4; ++l) {
    const double y = (l % 2 ? 0.05 : -0.05), z0 = l < 2 ? 0.25 : 0.45, dz = l < 2 ? -0.07 : -0.05;
    std::string previous = "waist";
    for (int k = 0; k < 6; ++k) {
      const std::string body = std::string(limbs[l]) + std::to_string(k + 1);
      const double z = z0 + dz * (k < 3 ? 0 : k - 2);
      text += "  - {name: " + body + ", mass: {mass: 0.05, com: [0, " + std::to_string(y) + ", " +
              std::to_string(z) + "], inertia: [1e-5, 1e-5, 1e-5]}}\n";
      joints += "  - {name: " + body + "_j, type: revolute, first: " + previous +
                ", second: " + body + ", s: " + axes[k] + ", s0: [" + (k == 3 ? "0.02" : "0") +
                ", " + std::to_string(y) + ", " + std::to_string(z) + "]}\n";
      previous = body;
    }
    const double zend = z0 + 3 * dz;
    drivers += "  - {name: " + std::string(limbs[l]) +
               "_pose, type: pose, first: ground, second: " + previous + ", at: [0, " +
               std::to_string(y) + ", " + std::to_string(zend) +
               "], x: " + (l == 0 ? "0.01*sin(2*t)" : "0") + ", y: " + std::to_string(y) +
               ", z: " + std::to_string(zend) + (l == 0 ? " + 0.005*(1 - cos(2*t))" : "") +
               ", rotations: [{axis: z, value: 0}, {axis: y, value: 0}, {axis: x, value: 0}]}\n";
  }
  return text + joints + drivers + "step: {t0: 0, t1: 1}\n";
}

inline std::vector<Case> closed_chains() {
  return {{"rsur", text_of(MECHGEN_SOURCE_DIR "/models/rsur.yaml")},
          {"chebyshev_spatial", text_of(MECHGEN_SOURCE_DIR "/models/chebyshev_spatial.yaml")},
          {"leg6_ik", leg6_inverse_kinematics()},
          {"hsuc", kHsucLoop},
          {"humanoid", humanoid()}};
}

}  // namespace mechgen::spatial
