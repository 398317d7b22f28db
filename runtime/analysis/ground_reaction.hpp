// Will it tip? The reaction of the floor on the ground body (PASIBOT's support foot) and its
// centre of pressure along the sole, which for a flat sole is the ZMP (seeds 001 and 003).
//
// The ground body is held by the floor: the floor's force R and moment M (about the ground-frame
// origin) balance everything the mechanism does to it, plus its own weight when it has a mass:
//   R = -(sum of the ground body's loads) - m_g g,     M = -(their moments) - r_g x m_g g.
// The same follows from the momentum rate of the whole mechanism, with no joint force at all:
//   R = sum m_i (a_i - g) - m_g g - F_ext,  M = sum (I_i al_i + r_i x m_i (a_i - g)) - r_g x m_g g
//       - (moments of F_ext and external torques),
// F_ext the `force` and `torque` elements (loads from outside; springs act between bodies).
// The sole is the segment heel -> toe (two points of the ground body); the centre of pressure is
// the point of it about which R has the moment M, u metres from the heel.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <string>
#include <vector>

#include "analysis/free_body.hpp"
#include "model/model.hpp"

namespace mechgen::analysis {

struct Reaction {
  Eigen::Vector2d force = Eigen::Vector2d::Zero();  // N, of the floor on the ground body
  double moment = 0;  // N m, about the ground-frame origin, counter-clockwise
};

// From the ground body's free body (its loads from the joints, drivers and applied loads).
Reaction reaction_from_joints(const FreeBody& ground, const Eigen::Vector2d& gravity);
// From the momentum rate of all bodies (index = body index, as FreeBodies::at returns them).
Reaction reaction_from_momentum(const Model& model, const std::vector<FreeBody>& bodies,
                                const Eigen::Vector2d& gravity);

// Distance from the heel, along heel -> toe, of the point of the sole line where the reaction's
// moment vanishes. NaN when R has no component across the sole (nothing presses the foot).
double centre_of_pressure(const Reaction& r, const Eigen::Vector2d& heel,
                          const Eigen::Vector2d& toe);

// The heel and toe: the named points, or by default the two points of the ground body farthest
// apart, the one with the smaller x (ground frame) as the heel. Throws ModelError for a name the
// ground body does not carry, or a ground body with fewer than two points.
std::pair<std::string, std::string> sole_points(const Model& model,
                                                const std::vector<double>& parameters,
                                                const std::string& heel, const std::string& toe);

struct ZmpSample {
  double t = 0;
  Reaction reaction;  // from the joints
  Reaction momentum;  // the same from the momentum rate (a check)
  double normal = 0;  // R across the sole (N; > 0 presses the foot on the floor)
  double zmp = 0;     // from the heel along the sole (m)
  double heel_margin = 0, toe_margin = 0;  // zmp and length - zmp: negative = outside the sole
};

struct ZmpReport {
  std::string heel, toe;
  double sole_length = 0;
  std::vector<ZmpSample> samples;
  double min_margin = 0;  // smallest of all heel and toe margins
  double min_margin_t = 0;
  std::string min_margin_end;               // heel or toe
  double min_normal = 0;                    // smallest normal force
  int inside = 0;                           // samples with the ZMP on the sole (0 <= zmp <= length)
  double inside_t0 = NAN, inside_t1 = NAN;  // the first and last of them (NaN when none)
  double largest_disagreement = 0;  // max |reaction - momentum| (force N, moment / length N)
};

ZmpReport zmp_over(const Model& model, const std::vector<double>& parameters,
                   const std::vector<std::string>& columns,
                   const std::vector<std::vector<double>>& rows, const std::string& heel = "",
                   const std::string& toe = "");

}  // namespace mechgen::analysis
