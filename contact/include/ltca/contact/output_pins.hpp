#pragma once
// The output pins of a cycloidal drive, the W mechanism (docs/stage.md): `count` pins of
// radius r_w on the output member at radius R_w, each in a hole of radius r_h of the disc. Pin j
// sits at alpha_j = 2 pi j / count + phase in the output member's frame (from +X at crank 0); its
// hole sits at the same place in the disc's body frame. At the nominal poses (the output member
// turned as the disc, geometry::Kinematics) every pin centre is offset from its hole centre by
// the eccentricity, so the no-load clearance is r_h - r_w - e.
//
// A pin touches its hole on the line of the two centres: the contact is an internal line contact
// (the [contact] law with the hole's concave curvature -1/r_h: OutputPinLaw). Its approach is
// |P_j - H_j| - (r_h - r_w); the force on the disc acts along n_j = (P_j - H_j) / |P_j - H_j|, the
// force on the pin along -n_j.
#include <vector>

#include <Eigen/Core>

#include "ltca/contact/holes.hpp"
#include "ltca/contact/laws.hpp"
#include "ltca/contact/material.hpp"
#include "ltca/geometry/kinematics.hpp"

namespace ltca::contact {

struct OutputPins {
  static constexpr int kMaxCount = 64;  ///< W mechanisms have 4 to 16
  int count = 0;               ///< pins (deck: [output] count)
  double pin_radius = 0.0;     ///< r_w, mm
  double circle_radius = 0.0;  ///< R_w, mm
  double hole_radius = 0.0;    ///< r_h, mm
  double phase = 0.0;          ///< rad, of pin 0 from +X at crank 0
  /// Each hole's position deviation in the disc (contact/holes.hpp); empty: none. Every disc
  /// takes the same (discs machined together in a stack).
  HoleDeviations hole_deviation;
  /// Throws std::invalid_argument naming the `[output]` key unless 3 <= count <= kMaxCount, the
  /// radii are finite and positive, r_h >= r_w + eccentricity (a pin would overlap its hole at no
  /// load) and neighbouring holes do not overlap, and the hole deviations are one finite pair per hole.
  void Validate(double eccentricity) const;
};

/// One pin against its hole, and the first-order change of its approach with the poses.
struct OutputPinContact {
  int pin = 0;
  Eigen::Vector2d pin_centre = Eigen::Vector2d::Zero();   ///< P_j, fixed frame, mm
  Eigen::Vector2d hole_centre = Eigen::Vector2d::Zero();  ///< H_j, fixed frame, mm
  Eigen::Vector2d normal = Eigen::Vector2d::UnitX();      ///< n_j, unit, from H_j towards P_j
  double gap = 0.0;  ///< r_h - r_w - |P_j - H_j|, mm (< 0: pressed)
  /// d(approach) / d(disc translation) = -n_j (dimensionless).
  Eigen::Vector2d translation_gradient = Eigen::Vector2d::Zero();
  /// d(approach) / d(disc rotation) = -n_j . perp(H_j - disc centre), mm/rad.
  double disc_arm = 0.0;
  /// d(approach) / d(output rotation) = n_j . perp(P_j), mm/rad (output member about the origin).
  double output_arm = 0.0;
};

/// The law of an output pin in its hole: a conformal line contact, the pin of radius
/// r_w inside the hole's concave radius r_h, 1/rho* = 1/r_w - 1/r_h (Johnson, Contact Mechanics,
/// 1985, section 4.1: a concave surface's radius of curvature is negative in the relative
/// curvature 1/R = 1/R_1 + 1/R_2; section 4.2(b) for the cylinders' line contact). Under either
/// [contact] rho_convention: the convention is how the pin-ring mesh takes the cycloid's curvature
/// (docs/contact.md), never the hole's, whose sign is its geometry. The deck's law kind, linear
/// stiffness and log cap (log_radius_cap resolved, > 0); the disc is the law's first body and the
/// pin its second (material's cycloid and pin constants); never seated (a seat is the ring pins').
/// length: the pin's contact length, mm. hole_log_radius > 0: the disc's (hole's) term of the
/// hertz-line logarithm takes exactly this radius, mm (an elastic disc body whose holes are condensed
/// with the flank: the Hertz contact's local field beyond the body's uniform patch, w0 / sqrt(e),
/// as the flank's, ContactSettings::cycloid_log_radius); 0: the rigid disc's, min(r_h, cap).
ContactLaw OutputPinLaw(const ContactSettings& contact, const Material& material, const OutputPins& pins,
                        double length, double log_radius_cap, double hole_log_radius = 0.0);

/// Every pin at the given disc pose (fixed frame) and output-member rotation (rad, about the
/// pin-circle centre). The centres must not coincide (|P_j - H_j| > 0: then the contact
/// direction is undefined; throws std::domain_error).
std::vector<OutputPinContact> EvaluateOutputPins(const OutputPins& pins, const geometry::Pose& disc,
                                                 double output_rotation);

}  // namespace ltca::contact
