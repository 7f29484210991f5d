#include "ltca/app/validation.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <sstream>

#include <fmt/format.h>

#include "ltca/contact/unloaded.hpp"
#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/analysis/efficiency.hpp"
#include "ltca/analysis/sweep.hpp"
#include "ltca/solvers/registry.hpp"

namespace ltca::app {
namespace {

namespace fs = std::filesystem;
using units::RadToArcsec;
using units::RadToDeg;

// ---- shared figures -------------------------------------------------------------------------

struct Loaded {
  double mean_te = 0, pp_te = 0, mean_pins = 0, max_stress = 0, max_force = 0;
  int pins_min = 0, pins_max = 0;
  SolverStatus status = SolverStatus::kNotSolved;
};

Loaded Summarise(const analysis::SweepResult& sweep) {
  Loaded l;
  l.mean_te = RadToArcsec(sweep.summary.mean_te);
  l.pp_te = RadToArcsec(sweep.summary.pp_te);
  l.pins_min = sweep.summary.contacts_min;
  l.pins_max = sweep.summary.contacts_max;
  l.max_stress = sweep.summary.max_contact_stress;
  l.max_force = sweep.summary.max_pin_force;
  l.status = sweep.summary.status;
  // A closed period's repeated last state weighs once.
  const std::size_t n = sweep.positions.size() - (sweep.summary.closed_period && sweep.positions.size() > 1 ? 1 : 0);
  for (std::size_t i = 0; i < n; ++i) l.mean_pins += sweep.positions[i].contacts;
  l.mean_pins /= static_cast<double>(n);
  return l;
}

Loaded Solve(const Deck& deck, const std::string& solver = "bisection") {
  SolverOptions options = deck.solver;
  options.name = solver;
  return Summarise(SolveDeckSweep(deck, options));
}

struct Backlash {
  double mean = 0, pp = 0;  // arcsec
};

Backlash UnloadedSweep(const Deck& deck) {
  const auto sweep = contact::AnalyseUnloadedSweep(deck.MakeModel(), deck.sweep.CrankAngles());
  return {RadToArcsec(sweep.mean_backlash), RadToArcsec(sweep.pp_backlash)};
}

std::string Percent(double ours, double published) {
  return fmt::format("{:+.2f} %", 100.0 * (ours - published) / std::abs(published));
}
double Rel(double ours, double published) { return std::abs(ours - published) / std::abs(published); }

// Every verdict follows from a comparison of our value with the published one at the row's
// stated tolerance: `match` when it holds, "not reproducible" when it does not. A row whose
// published input is inconsistent gets its verdict the same way, so it would change if the
// computation did.
Verdict Within(bool holds, Verdict match) { return holds ? match : Verdict::kNotReproducible; }

// Li numbers his pins clockwise; his No. 40 is our pin 1 (index 0) at crank 0, the one integer
// offset that puts his first-contact pin No. 35 on our first-contact pin. Every other published
// pin number is then an independent check.
int LiNumber(int index, int pin_count) { return (pin_count - index - 1) % pin_count + 1; }

struct Builder {
  std::vector<ValidationRow> rows;
  std::string paper;
  void Add(std::string id, std::string quantity, std::string published, std::string ours, std::string difference,
           Verdict verdict, std::string note, std::string command) {
    rows.push_back({std::move(id), paper, std::move(quantity), std::move(published), std::move(ours),
                    std::move(difference), verdict, std::move(note), std::move(command)});
  }
};

// ---- the papers -----------------------------------------------------------------------------

void Chen(const fs::path& dir, Builder& b) {
  b.paper = "Chen 2008: geometry (section 3)";
  struct Case {
    const char* deck;
    const char* label;
    double phi, ratio;  // printed; ratio < 0: not printed
  };
  const Case cases[] = {{"d1", "(12, 11, 90, 7, 4), d = 1", 16.36, -1},
                        {"d2", "(24, 22, 90, 7, 4), d = 2", 8.77, 6.43},
                        {"d3", "(36, 33, 90, 7, 4), d = 3", 5.22, 5.74},
                        {"dm1", "(15, 16, 120, 10, 5), d = -1", 11.25, -1}};
  const auto judge = [](double ours, double published) {
    const double r = Rel(ours, published);
    return r <= 5e-4 ? Verdict::kReproduced : (r <= 5e-3 ? Verdict::kReproducedInexact : Verdict::kNotReproducible);
  };
  for (const Case& c : cases) {
    const Deck deck = LoadDeck(dir / "chen2008" / (std::string(c.deck) + ".toml"));
    const geometry::RealPair real = deck.MakeRealPair();
    const geometry::CycloidProfile& profile = real.profile();
    const std::string cmd = fmt::format("ltca geometry cases/chen2008/{}.toml", c.deck);
    const double phi = RadToDeg(profile.phi_max());
    const Verdict v = judge(phi, c.phi);
    b.Add(fmt::format("chen2008.{}.phi_max", c.deck), fmt::format("phi_max (eq. 16), {}", c.label),
          fmt::format("{:.2f} deg", c.phi), fmt::format("{:.6f} deg", phi), Percent(phi, c.phi), v,
          v == Verdict::kReproduced ? ""
          : v == Verdict::kReproducedInexact
              ? "the printed root of eq. 16 is inexact; the exact root satisfies eq. 16 to 1e-12 R_Z"
              : "the printed root of eq. 16 is 0.52 % above the exact root, more than its two decimals allow; "
                "the printed contact ratio follows from it through eq. 27",
          cmd);
    if (c.ratio > 0) {
      const double ratio = profile.contact_ratio();
      const Verdict vr = judge(ratio, c.ratio);
      b.Add(fmt::format("chen2008.{}.contact_ratio", c.deck), fmt::format("contact ratio (eq. 27), {}", c.label),
            fmt::format("{:.2f}", c.ratio), fmt::format("{:.4f}", ratio), Percent(ratio, c.ratio), vr,
            "follows from the printed (inexact) phi_max through eq. 27", cmd);
    }
  }
}

void LiuGeometryAndLoaded(const fs::path& dir, Builder& b) {
  b.paper = "Liu 2021: Table 1 pair (sections 4 and 5.2)";
  const Deck signed_deck = LoadDeck(dir / "liu2021_table1.toml");
  const Deck abs_deck = LoadDeck(dir / "liu2021_table1_absolute.toml");
  {
    const geometry::RealPair real = signed_deck.MakeRealPair();
    const geometry::CycloidProfile& profile = real.profile();
    const double alpha = RadToDeg(profile.alpha_max());
    const double printed = 54.3692;
    // Tolerance: half a unit of the printed fourth decimal.
    const Verdict v = Within(std::abs(alpha - printed) <= 0.5e-4, Verdict::kReproduced);
    const auto& pair = signed_deck.pair;
    const double k1_needed = std::sin(units::DegToRad(printed));  // eq. 2 peaks at arcsin K1
    b.Add("liu2021.alpha_max", "alpha_max, eq. 2 (section 4)", fmt::format("{:.4f} deg", printed),
          fmt::format("{:.4f} deg", alpha), fmt::format("{:+.4f} deg", alpha - printed), v,
          fmt::format("tolerance 5e-5 deg (the printed digits); eq. 2 peaks at arcsin(z_p e / R_p) = arcsin({:.4f}); "
                      "{:.4f} deg needs K1 = {:.5f} (R_p = {:.3f} mm or e = {:.5f} mm)",
                      pair.CurtateCoefficient(), printed, k1_needed,
                      pair.pin_count * pair.eccentricity / k1_needed,
                      k1_needed * pair.pin_circle_radius / pair.pin_count),
          "ltca geometry");
  }
  const Loaded abs = Solve(abs_deck), sgn = Solve(signed_deck);
  const std::string cmd_abs = "ltca solve cases/liu2021_table1_absolute.toml";
  b.Add("liu2021.t1.mean_te.absolute", "mean TE, perfect surfaces (Fig. 7a)", "-4.5206 arcsec",
        fmt::format("{:.4f} arcsec", abs.mean_te), Percent(abs.mean_te, -4.5206),
        Rel(abs.mean_te, -4.5206) <= 0.015 ? Verdict::kReproducedConvention : Verdict::kNotReproducible,
        "rho_convention = absolute (|rho_c| in eq. 25); tolerance 1.5 %", cmd_abs);
  b.Add("liu2021.t1.mean_te.signed", "mean TE, perfect surfaces, signed rho (physically correct)", "-4.5206 arcsec",
        fmt::format("{:.4f} arcsec", sgn.mean_te), Percent(sgn.mean_te, -4.5206),
        Rel(sgn.mean_te, -4.5206) <= 0.015 ? Verdict::kReproduced : Verdict::kNotReproducible,
        "the conformal contact in the concave flank (signed rho*) is stiffer at the root than Liu's |rho_c|: the "
        "published value needs the absolute convention",
        "ltca solve cases/liu2021_table1.toml");
  b.Add("liu2021.t1.max_stress.absolute", "maximum contact stress (Fig. 7e)", "1067.50 MPa",
        fmt::format("{:.2f} MPa", abs.max_stress), Percent(abs.max_stress, 1067.50),
        Rel(abs.max_stress, 1067.50) <= 0.015 ? Verdict::kReproducedConvention : Verdict::kNotReproducible,
        "rho_convention = absolute; tolerance 1.5 %", cmd_abs);
  const std::string pins = fmt::format("{} to {}", abs.pins_min, abs.pins_max);
  b.Add("liu2021.t1.pins", "pins in contact (Fig. 7b)", "19 to 20", pins, "",
        (abs.pins_min == 19 && abs.pins_max == 20) ? Verdict::kReproduced : Verdict::kNotReproducible,
        "linearised kinematics; a pin counts above 1e-6 of the largest force (a pin exactly on the line of centres "
        "carries ~1e-12 of it)",
        cmd_abs);
  b.Add("liu2021.t1.pp_te", "peak-to-peak TE (Fig. 7a)", "0.0531 arcsec", fmt::format("{:.4f} arcsec", abs.pp_te),
        Percent(abs.pp_te, 0.0531),
        (abs.pp_te > 0.0531 / 2 && abs.pp_te < 0.0531 * 2) ? Verdict::kSameOrder : Verdict::kNotReproducible,
        "the ripple comes from pins crossing the inflection point; it depends on how the curvature singularity is "
        "sampled (Liu: 800 elements; here: analytic, |rho_c| capped at R_p in the logarithm), which the paper leaves "
        "open",
        cmd_abs);
  const Backlash t1b = UnloadedSweep(abs_deck);
  b.Add("liu2021.t1.backlash", "backlash, perfect surfaces (Fig. 7a)", "0", fmt::format("{:.2e} arcsec", t1b.mean), "",
        std::abs(t1b.mean) < 1e-6 ? Verdict::kReproduced : Verdict::kNotReproducible, "",
        "ltca backlash cases/liu2021_table1_absolute.toml");

  const Deck base = LoadDeck(dir / "liu2021_sec52_base.toml");
  const Loaded bl = Solve(base);
  b.Add("liu2021.s52.pins", "pins in contact, base modification (section 5.2 text)", "6 to 7",
        fmt::format("{} to {}", bl.pins_min, bl.pins_max), "",
        (bl.pins_min == 6 && bl.pins_max == 7) ? Verdict::kReproduced : Verdict::kNotReproducible, "",
        "ltca solve cases/liu2021_sec52_base.toml");

  // Fig. 11: slopes by central differences of +-1 um around the base modification.
  const auto slope = [&](auto set) {
    Deck lo = base, hi = base;
    set(lo.errors, -1e-3);
    set(hi.errors, +1e-3);
    const double te = (Solve(hi).mean_te - Solve(lo).mean_te) / 2.0;
    const double bk = (UnloadedSweep(hi).mean - UnloadedSweep(lo).mean) / 2.0;
    return std::pair{te, bk};
  };
  const auto [te_pin, bk_pin] = slope([](geometry::ManufacturingErrors& e, double v) { e.pin_circle_deviation = v; });
  const auto [te_dia, bk_dia] = slope([](geometry::ManufacturingErrors& e, double v) {
    e.pin_circle_deviation = v;
    e.pin_circle_reading = geometry::ManufacturingErrors::PinCircleReading::kDiameter;
  });
  const auto [te_layer, bk_layer] = slope([](geometry::ManufacturingErrors& e, double v) { e.profile_layer = v; });
  const std::string cmd11 = "ltca solve / ltca backlash cases/liu2021_sec52_base.toml with [errors] at -1 and +1 um";
  b.Add("liu2021.fig11.backlash_pin_circle", "mean backlash slope vs pin-circle deviation (Fig. 11)", "4.7578 arcsec/um",
        fmt::format("{:.4f} arcsec/um", bk_pin), Percent(bk_pin, 4.7578),
        Rel(bk_pin, 4.7578) <= 1e-3 ? Verdict::kReproducedConvention : Verdict::kNotReproducible,
        "radius reading of eq. 5 (pins move by delta_Rp); tolerance 0.1 %", cmd11);
  b.Add("liu2021.fig11.backlash_pin_circle_diameter", "the same, eq. 5 as printed (pins move by delta_Rp / 2)",
        "4.7578 arcsec/um", fmt::format("{:.4f} arcsec/um", bk_dia), Percent(bk_dia, 4.7578),
        Rel(bk_dia, 4.7578) <= 1e-3 ? Verdict::kReproduced : Verdict::kNotReproducible,
        "eq. 5's delta_Rp / 2 (a diameter deviation) halves the slope: Fig. 11 used the radius", cmd11);
  b.Add("liu2021.fig11.te_pin_circle", "mean TE slope vs pin-circle deviation (Fig. 11)", "-2.6029 arcsec/um",
        fmt::format("{:.4f} arcsec/um", te_pin), Percent(te_pin, -2.6029),
        Rel(te_pin, -2.6029) <= 1e-2 ? Verdict::kReproducedConvention : Verdict::kNotReproducible,
        "radius reading of eq. 5, absolute rho; tolerance 1 %", cmd11);
  b.Add("liu2021.fig11.backlash_layer", "mean backlash slope vs cycloid profile upper deviation (Fig. 11)",
        "-8.4004 arcsec/um", fmt::format("{:.4f} arcsec/um", bk_layer), Percent(bk_layer, -8.4004),
        Rel(bk_layer, -8.4004) <= 4e-2 ? Verdict::kReproducedConvention : Verdict::kNotReproducible,
        "the upper deviation modelled as a uniform layer (Liu moves a zone of random element deviations); tolerance "
        "4 %",
        cmd11);
  b.Add("liu2021.fig11.te_layer", "mean TE slope vs cycloid profile upper deviation (Fig. 11)", "4.1848 arcsec/um",
        fmt::format("{:.4f} arcsec/um", te_layer), Percent(te_layer, 4.1848),
        Rel(te_layer, 4.1848) <= 1.5e-2 ? Verdict::kReproducedConvention : Verdict::kNotReproducible,
        "uniform-layer model, absolute rho; tolerance 1.5 %", cmd11);
}

// Liu 2021 sections 5.2-5.3: what the error tooth surfaces do. Liu prints plots and trends, not
// numbers, for these cases; each row states the trend and checks it on our results.
struct Harmonic {
  double share = 0.0;  // share of the TE variance in the first crank harmonic
  double phase = 0.0;  // rad, of a1 cos(theta) + b1 sin(theta)
};

// TE over one crank revolution (the first position repeats as the last: dropped).
Harmonic FirstHarmonic(const std::vector<analysis::PositionResult>& positions) {
  const std::size_t n = positions.size() - 1;
  double mean = 0.0, a = 0.0, b = 0.0, var = 0.0;
  for (std::size_t i = 0; i < n; ++i) mean += positions[i].result.te / static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = positions[i].result.te - mean, c = positions[i].crank;
    a += 2.0 * t * std::cos(c) / static_cast<double>(n);
    b += 2.0 * t * std::sin(c) / static_cast<double>(n);
    var += t * t / static_cast<double>(n);
  }
  return {0.5 * (a * a + b * b) / var, std::atan2(b, a)};
}

struct Revolution {
  Loaded loaded;
  Backlash backlash;
  Harmonic harmonic;
  analysis::SweepResult sweep;
};

Revolution SolveRevolution(const Deck& deck) {
  Revolution r;
  SolverOptions options = deck.solver;
  options.name = "bisection";
  r.sweep = SolveDeckSweep(deck, options);
  r.loaded = Summarise(r.sweep);
  r.backlash = UnloadedSweep(deck);
  r.harmonic = FirstHarmonic(r.sweep.positions);
  return r;
}

bool Increasing(const std::vector<double>& v) {
  for (std::size_t i = 1; i < v.size(); ++i) {
    if (!(v[i] > v[i - 1])) return false;
  }
  return true;
}

std::string Joined(const std::vector<double>& v, int decimals) {
  std::string out;
  for (const double x : v) out += (out.empty() ? "" : " / ") + fmt::format("{:.{}f}", x, decimals);
  return out;
}

bool Decreasing(std::vector<double> v) {
  for (double& x : v) x = -x;
  return Increasing(v);
}

/// Liu 2021 section 5.2: the pitch deviation dominates the TE.
void LiuPitch(const fs::path& dir, Builder& b) {
  const Deck base = LoadDeck(dir / "liu2021_sec52_base.toml");
  const Deck pitch = LoadDeck(dir / "liu2021_sec52_pitch.toml");
  Deck base_rev = base;  // the error-free pair over the same revolution
  base_rev.sweep = pitch.sweep;
  const Loaded none = Solve(base_rev), with_pitch = Solve(pitch);
  b.Add("liu2021.s52.pitch.pins", "pins in contact with the pitch deviation F_p = 15 um (Fig. 12a)",
        "3 to 10 (6 to 7 without)", fmt::format("{} to {} ({} to {} without)", with_pitch.pins_min, with_pitch.pins_max,
                                                none.pins_min, none.pins_max),
        "", (with_pitch.pins_min < none.pins_min && with_pitch.pins_max > none.pins_max) ? Verdict::kHolds : Verdict::kFails,
        "the range widens both ways (a trend: Liu's deviation is a plot, Fig. 9, and ours a realisation of the same "
        "recipe, sine plus N(0, 2 um), scaled to F_p = 15 um)",
        "ltca solve cases/liu2021_sec52_pitch.toml");
  Deck circle = base_rev, layer = base_rev;
  circle.errors.pin_circle_deviation = 0.004;  // Liu's delta_Rp = 4 um
  layer.errors.profile_layer = 0.003;          // F_alpha^c upper deviation 3 um, as a uniform layer
  const double pp_circle = Solve(circle).pp_te, pp_layer = Solve(layer).pp_te;
  b.Add("liu2021.s52.pitch.ppte", "PPTE: the pitch deviation is its main source (Fig. 10a)",
        "F_p dominates; delta_Rp and F_alpha^c add little",
        fmt::format("{:.3f} arcsec with F_p; {:.3f} with delta_Rp = 4 um; {:.3f} with a 3 um layer; {:.3f} without",
                    with_pitch.pp_te, pp_circle, pp_layer, none.pp_te),
        "", with_pitch.pp_te > 10.0 * std::max({pp_circle, pp_layer, none.pp_te}) ? Verdict::kHolds : Verdict::kFails,
        "holds when the PPTE with F_p exceeds ten times each of the others", "ltca solve cases/liu2021_sec52_pitch.toml");
}

/// Liu 2021 section 5.3: the centre distance deviation dy, fixed in the frame.
void LiuCentreDistance(const fs::path& dir, Builder& b) {
  const Deck dy_deck = LoadDeck(dir / "liu2021_sec53_dy.toml");
  std::vector<double> pp_te[2], pp_b[2], mb[2], mte[2];
  double worst_share = 1.0;
  for (int sign = 0; sign < 2; ++sign) {
    for (const double um : {3.0, 6.0, 9.0}) {
      Deck d = dy_deck;
      d.assembly.centre_dy = (sign == 0 ? 1.0 : -1.0) * units::UmToMm(um);
      const Revolution r = SolveRevolution(d);
      pp_te[sign].push_back(r.loaded.pp_te);
      pp_b[sign].push_back(r.backlash.pp);
      mb[sign].push_back(r.backlash.mean);
      mte[sign].push_back(r.loaded.mean_te);
      worst_share = std::min(worst_share, r.harmonic.share);
    }
  }
  const std::string cmd_dy = "ltca solve / ltca backlash cases/liu2021_sec53_dy.toml --set errors.centre_dy_mm=+-0.003, 0.006, 0.009";
  b.Add("liu2021.s53.dy.harmonic", "TE under dy = +-3, 6, 9 um is a harmonic of the crank angle (Fig. 13a)",
        "harmonic over one revolution", fmt::format("first crank harmonic carries >= {:.1f} % of the TE variance", 100.0 * worst_share),
        "", worst_share >= 0.9 ? Verdict::kHolds : Verdict::kFails, "holds at >= 90 % of the variance in every case", cmd_dy);
  b.Add("liu2021.s53.dy.ppte", "PPTE grows with |dy| (Fig. 13c)", "grows",
        fmt::format("{} arcsec (+dy); {} (-dy)", Joined(pp_te[0], 2), Joined(pp_te[1], 2)), "",
        Increasing(pp_te[0]) && Increasing(pp_te[1]) ? Verdict::kHolds : Verdict::kFails, "", cmd_dy);
  b.Add("liu2021.s53.dy.ppb", "peak-to-peak backlash grows with |dy| (Fig. 13d)", "grows",
        fmt::format("{} arcsec (+dy); {} (-dy)", Joined(pp_b[0], 2), Joined(pp_b[1], 2)), "",
        Increasing(pp_b[0]) && Increasing(pp_b[1]) ? Verdict::kHolds : Verdict::kFails, "", cmd_dy);
  b.Add("liu2021.s53.dy.mb", "mean backlash falls with |dy| (Fig. 13d)", "falls",
        fmt::format("{} arcsec (+dy); {} (-dy)", Joined(mb[0], 3), Joined(mb[1], 3)), "",
        Decreasing(mb[0]) && Decreasing(mb[1]) ? Verdict::kHolds : Verdict::kFails, "", cmd_dy);
  b.Add("liu2021.s53.dy.mte", "mean TE (signed) increases with |dy| (Fig. 13c)", "increases",
        fmt::format("{} arcsec (+dy); {} (-dy)", Joined(mte[0], 3), Joined(mte[1], 3)), "",
        Increasing(mte[0]) && Increasing(mte[1]) ? Verdict::kHolds : Verdict::kFails,
        "the TE is negative on the drive flank (Liu eq. 16, Fig. 7a): increasing, it comes closer to zero. Liu: the "
        "effect on the MB is larger than on the MTE",
        cmd_dy);
}

/// Liu 2021 section 5.3: misalignment phi (XZ) and gamma (YZ), about face B.
void LiuMisalignment(const fs::path& dir, Builder& b) {
  const Deck phi_deck = LoadDeck(dir / "liu2021_sec53_phi.toml");
  std::vector<Revolution> phi, gamma;
  for (const double deg : {0.01, 0.02, 0.03}) {
    Deck p = phi_deck, g = phi_deck;
    p.assembly.misalignment_xz = units::DegToRad(deg);
    g.assembly.misalignment_xz = 0.0;
    g.assembly.misalignment_yz = units::DegToRad(deg);
    phi.push_back(SolveRevolution(p));
    gamma.push_back(SolveRevolution(g));
  }
  const Revolution& p2 = phi[1];
  const Revolution& g2 = gamma[1];
  const std::string cmd_mis = "ltca solve / ltca backlash cases/liu2021_sec53_phi.toml, cases/liu2021_sec53_gamma.toml";
  b.Add("liu2021.s53.misalign.equal", "phi and gamma of 0.02 deg: equal PPTE and peak-to-peak backlash (Fig. 15)", "equal",
        fmt::format("PPTE {:.4f} / {:.4f} arcsec, PPB {:.4f} / {:.4f} arcsec", p2.loaded.pp_te, g2.loaded.pp_te,
                    p2.backlash.pp, g2.backlash.pp),
        Percent(g2.loaded.pp_te, p2.loaded.pp_te),
        Rel(g2.loaded.pp_te, p2.loaded.pp_te) <= 0.01 && Rel(g2.backlash.pp, p2.backlash.pp) <= 0.01 ? Verdict::kHolds
                                                                                                     : Verdict::kFails,
        "tolerance 1 %: the sweep samples the revolution every 5 deg", cmd_mis);
  const double shift = RadToDeg(std::remainder(g2.harmonic.phase - p2.harmonic.phase, 2.0 * units::kPi));
  b.Add("liu2021.s53.misalign.phase", "phase of the TE curves, gamma against phi (Fig. 15a, c)", "90 deg",
        fmt::format("{:.2f} deg", shift), fmt::format("{:+.2f} deg", std::abs(shift) - 90.0),
        std::abs(std::abs(shift) - 90.0) <= 2.0 ? Verdict::kHolds : Verdict::kFails,
        "first crank harmonic of the TE; tolerance 2 deg", cmd_mis);
  std::vector<double> pp_phi, ppb_phi, mb_phi;
  for (const auto& r : phi) pp_phi.push_back(r.loaded.pp_te), ppb_phi.push_back(r.backlash.pp), mb_phi.push_back(r.backlash.mean);
  b.Add("liu2021.s53.misalign.trend", "phi 0.01, 0.02, 0.03 deg: PPTE and PPB grow, mean backlash falls (Fig. 15)",
        "grow / grow / falls",
        fmt::format("PPTE {} arcsec; PPB {}; MB {}", Joined(pp_phi, 3), Joined(ppb_phi, 3), Joined(mb_phi, 3)), "",
        Increasing(pp_phi) && Increasing(ppb_phi) && Decreasing(mb_phi) ? Verdict::kHolds : Verdict::kFails, "", cmd_mis);
  // Eccentric load: the load centroid of a pin moves off the mid-plane (Fig. 17d: pins 14-16 at 90 deg).
  double off = 0.0;
  int worst_pin = -1;
  double worst_crank = 0.0;
  for (const auto& pos : p2.sweep.positions) {
    for (std::size_t j = 0; j < pos.load_centroid.size(); ++j) {
      if (!(pos.pin_force[j] > 0.05 * p2.loaded.max_force)) continue;
      const double d = std::abs(pos.load_centroid[j] - 0.5 * phi_deck.pair.face_width);
      if (d > off) off = d, worst_pin = static_cast<int>(j), worst_crank = pos.crank;
    }
  }
  b.Add("liu2021.s53.misalign.eccentric", "phi = 0.02 deg loads pins eccentrically (Fig. 17d-f)",
        "serious eccentric load on some pins",
        fmt::format("load centroid of pin {} at crank {:.0f} deg is {:.2f} mm off the mid-plane (B = {:g} mm)", worst_pin + 1,
                    RadToDeg(worst_crank), off, phi_deck.pair.face_width),
        "", off > 0.1 * phi_deck.pair.face_width ? Verdict::kHolds : Verdict::kFails,
        "holds when a pin carrying over 5 % of the largest force has its centroid more than 10 % of B off the mid-plane",
        "ltca solve cases/liu2021_sec53_phi.toml --json -  (load_centroid_mm)");
  Deck aligned = phi_deck;
  aligned.assembly.misalignment_xz = 0.0;
  const double mean_pins_aligned = Solve(aligned).mean_pins;
  b.Add("liu2021.s53.misalign.pins", "phi = 0.02 deg raises the mean number of pins in contact (Fig. 16a)", "rises",
        fmt::format("{:.2f} (aligned {:.2f})", p2.loaded.mean_pins, mean_pins_aligned), "",
        p2.loaded.mean_pins > mean_pins_aligned ? Verdict::kHolds : Verdict::kFails, "", "ltca solve cases/liu2021_sec53_phi.toml");
}

void LiuErrorSurfaces(const fs::path& dir, Builder& b) {
  b.paper = "Liu 2021: error tooth surfaces (sections 5.2-5.3)";
  LiuPitch(dir, b);
  LiuCentreDistance(dir, b);
  LiuMisalignment(dir, b);
}

// "1-4", "4, 8, 9-20": the case numbers of a group, consecutive runs joined.
std::string CaseList(std::vector<int> numbers) {
  std::sort(numbers.begin(), numbers.end());
  std::string out;
  for (std::size_t i = 0; i < numbers.size();) {
    std::size_t j = i;
    while (j + 1 < numbers.size() && numbers[j + 1] == numbers[j] + 1) ++j;
    out += (out.empty() ? "" : ", ") +
           (j == i ? fmt::format("{}", numbers[i]) : fmt::format("{}-{}", numbers[i], numbers[j]));
    i = j + 1;
  }
  return out;
}

std::vector<LiuTable2Row> LiuTable2(const fs::path& dir, Builder& b) {
  b.paper = "Liu 2021: Table 2 modification cases (section 5.1, Fig. 8; plots only: the claims are tested)";
  std::vector<LiuTable2Row> table;
  for (int i = 1; i <= 20; ++i) {  // Liu's Table 2 lists 20 cases
    const Deck deck = LoadDeck(dir / "liu2021_table2" / fmt::format("case{:02d}.toml", i));
    const Loaded l = Solve(deck);
    const Backlash bk = UnloadedSweep(deck);
    // The amounts are the deck's [modification] (mm), listed in um as Liu prints them.
    table.push_back({i, units::MmToUm(deck.modification.pin_radius), units::MmToUm(deck.modification.pin_circle_radius), l.mean_te,
                     l.pp_te, bk.mean, bk.pp, l.mean_pins, l.max_stress});
  }
  // The groups Liu's claims speak of, selected by the amounts the decks hold.
  using Group = std::vector<const LiuTable2Row*>;
  const auto same = [](double a, double z) { return std::abs(a - z) < 1e-6; };  // um
  const auto select = [&](auto belongs, auto amount) {
    Group g;
    for (const auto& r : table) {
      if (belongs(r)) g.push_back(&r);
    }
    std::sort(g.begin(), g.end(), [&](const auto* x, const auto* y) { return amount(*x) < amount(*y); });
    return g;
  };
  const auto numbers = [](const Group& g) {
    std::vector<int> n;
    for (const auto* r : g) n.push_back(r->case_number);
    return n;
  };
  // Isometric only (dR_p = 0) and offset only (dR_rp = 0), by growing amount.
  const Group iso = select([&](const LiuTable2Row& r) { return same(r.d_rp_um, 0) && r.d_rrp_um > 0; },
                           [](const LiuTable2Row& r) { return r.d_rrp_um; });
  const Group off = select([&](const LiuTable2Row& r) { return same(r.d_rrp_um, 0) && r.d_rp_um < 0; },
                           [](const LiuTable2Row& r) { return -r.d_rp_um; });
  // The cases of 5 um radial clearance dR_rp - dR_p, in case order; the compound -dR_rp/-dR_p among them.
  const Group clearance = select([&](const LiuTable2Row& r) { return same(r.d_rrp_um - r.d_rp_um, 5); },
                                 [](const LiuTable2Row& r) { return r.case_number; });
  const Group compound = select([](const LiuTable2Row& r) { return r.d_rrp_um < 0 && r.d_rp_um < 0; },
                                [](const LiuTable2Row& r) { return r.case_number; });

  const auto increasing = [](const Group& g, auto get) {
    if (g.size() < 2) return false;  // nothing to grow: the claim is not shown
    for (std::size_t k = 1; k < g.size(); ++k) {
      if (!(get(*g[k]) > get(*g[k - 1]))) return false;
    }
    return true;
  };
  const auto abs_te = [](const LiuTable2Row& r) { return std::abs(r.mean_te_arcsec); };
  const auto mb = [](const LiuTable2Row& r) { return r.mean_backlash_arcsec; };
  const std::string cmd = "ltca solve / ltca backlash cases/liu2021_table2/caseNN.toml";
  const auto verdict = [](bool ok) { return ok ? Verdict::kHolds : Verdict::kFails; };
  b.Add("liu2021.t2.isometric_grows",
        fmt::format("|mean TE| and mean backlash grow with the isometric amount (cases {})", CaseList(numbers(iso))),
        "grow", "see the Table 2 listing", "", verdict(increasing(iso, abs_te) && increasing(iso, mb)), "", cmd);
  b.Add("liu2021.t2.offset_grows",
        fmt::format("|mean TE| and mean backlash grow with the offset amount (cases {})", CaseList(numbers(off))),
        "grow", "see the Table 2 listing", "", verdict(increasing(off, abs_te) && increasing(off, mb)), "", cmd);
  bool iso_worse = true;
  std::vector<int> iso_cases, off_cases;
  for (const double amount : {3.0, 4.0, 5.0}) {  // the equal amounts the claim compares, um
    const LiuTable2Row *i = nullptr, *o = nullptr;
    for (const auto* r : iso) {
      if (same(r->d_rrp_um, amount)) i = r;
    }
    for (const auto* r : off) {
      if (same(-r->d_rp_um, amount)) o = r;
    }
    iso_worse = iso_worse && i != nullptr && o != nullptr && abs_te(*i) > abs_te(*o) && mb(*i) > mb(*o);
    if (i != nullptr) iso_cases.push_back(i->case_number);
    if (o != nullptr) off_cases.push_back(o->case_number);
  }
  b.Add("liu2021.t2.isometric_worse",
        fmt::format("isometric worse than offset at equal amount (cases {} vs {})", CaseList(iso_cases),
                    CaseList(off_cases)),
        "worse", "see the Table 2 listing", "", verdict(iso_worse), "", cmd);
  const LiuTable2Row *best_mb = nullptr, *best_te = nullptr;
  for (const auto* r : clearance) {
    if (best_mb == nullptr || mb(*r) < mb(*best_mb)) best_mb = r;
    if (best_te == nullptr || abs_te(*r) < abs_te(*best_te)) best_te = r;
  }
  const auto in_compound = [&](const LiuTable2Row* r) {
    return r != nullptr && std::find(compound.begin(), compound.end(), r) != compound.end();
  };
  b.Add("liu2021.t2.compound_best",
        fmt::format("-dR_rp/-dR_p compound gives the smallest backlash and |mean TE| (cases {})",
                    CaseList(numbers(clearance))),
        "cases 9-12",
        fmt::format("backlash: case {}, |TE|: case {}", best_mb ? best_mb->case_number : 0,
                    best_te ? best_te->case_number : 0),
        "", verdict(in_compound(best_mb) && in_compound(best_te)), "", cmd);
  bool fewer = iso.size() >= 2 && off.size() >= 2;
  for (const Group* g : {&iso, &off}) {
    for (std::size_t k = 1; k < g->size(); ++k) {
      const auto& a = *(*g)[k - 1];
      const auto& z = *(*g)[k];
      fewer = fewer && z.mean_pins <= a.mean_pins && z.max_stress_mpa > a.max_stress_mpa;
    }
  }
  b.Add("liu2021.t2.fewer_pins_more_stress",
        fmt::format("larger amounts: fewer pins in contact, higher maximum stress ({}, {})", CaseList(numbers(iso)),
                    CaseList(numbers(off))),
        "fewer, higher", "see the Table 2 listing", "", verdict(fewer), "", cmd);
  return table;
}

/// The figures Li tables for one deck at its first crank (Li section 4): the loaded pins, the
/// largest force, deformation and pressure and their pins, the half-widths.
struct PinFigures {
  int pins = 0, first_no = 0, last_no = 0, max_force_no = 0, max_pressure_no = 0, max_deform_no = 0;
  double max_force = 0, max_deform = 0, min_half = INFINITY, max_half = 0, te_arcmin = 0, max_pressure = 0;
  double stated_pressure = 0;  // at the max-pressure pin, with the stated modulus 2.08e5 MPa
  std::vector<double> listed_half;  // at the pins Li's Table 2 lists
};

/// The pins Li's Table 2 lists, by Li's clockwise numbering, and the contact half-widths (mm) it
/// gives them.
constexpr int kLiListed[] = {24, 25, 26, 27, 36, 37, 38, 39};
constexpr double kLiListedHalfWidth[] = {0.15, 0.19, 0.24, 0.27, 0.44, 0.37, 0.34, 0.24};
static_assert(std::size(kLiListed) == std::size(kLiListedHalfWidth));

PinFigures AnalyseLi(const Deck& deck) {
  const contact::MeshModel model = deck.MakeModel();
  const solvers::LoadProblem problem(model, deck.sweep.crank_start, deck.contact, *deck.material, deck.load->torque,
                            contact::ContactKinematics::kLinearised);
  const auto r = solvers::MakeSolver("bisection")->Solve(problem, SolverOptions{});
  contact::Material stated = *deck.material;
  stated.young_modulus = stated.pin_young_modulus = 2.08e5;
  PinFigures f;
  f.te_arcmin = RadToArcsec(r.te) / 60.0;
  const double f_max = *std::max_element(r.force.begin(), r.force.end());
  std::vector<int> numbers;
  for (std::size_t i = 0; i < r.force.size(); ++i) {
    if (!(r.force[i] > analysis::kContactForceFraction * f_max)) continue;
    const int no = LiNumber(static_cast<int>(i), deck.pair.pin_count);
    numbers.push_back(no);
    const auto& law = problem.base_laws()[i];
    const double p = law.MaxPressure(r.force[i]);
    if (r.force[i] > f.max_force) f.max_force = r.force[i], f.max_force_no = no;
    if (r.approach[i] > f.max_deform) f.max_deform = r.approach[i], f.max_deform_no = no;
    if (p > f.max_pressure) {
      f.max_pressure = p, f.max_pressure_no = no;
      const auto& pin = problem.base_state().pins[i];
      f.stated_pressure = contact::ContactLaw(deck.contact, stated, pin.cycloid_curvature, pin.pin_radius,
                                              deck.pair.face_width, deck.pair.pin_circle_radius)
                              .MaxPressure(r.force[i]);
    }
    f.min_half = std::min(f.min_half, law.HalfWidth(r.force[i]));
    f.max_half = std::max(f.max_half, law.HalfWidth(r.force[i]));
  }
  for (const int no : kLiListed) {
    const auto i = static_cast<std::size_t>(deck.pair.pin_count - no);  // inverse of LiNumber
    f.listed_half.push_back(problem.base_laws()[i].HalfWidth(r.force[i]));
  }
  f.pins = static_cast<int>(numbers.size());
  f.first_no = *std::min_element(numbers.begin(), numbers.end());
  f.last_no = *std::max_element(numbers.begin(), numbers.end());
  return f;
}

void Li(const fs::path& dir, Builder& b) {
  b.paper = "Li: Table 1 pair (section 4, Table 2, Figs. 4-10)";
  const Deck stated = LoadDeck(dir / "li_table1.toml");
  const Deck hyp = LoadDeck(dir / "li_table1_hypothesis.toml");
  {
    const contact::MeshModel model(stated.pair, stated.modification, stated.errors);
    const auto tca = contact::AnalyseUnloaded(model, 0.0);
    const int no = LiNumber(tca.first_pin_c1, stated.pair.pin_count);
    b.Add("li.first_contact", "first-contact pin (Fig. 4)", "No. 35", fmt::format("No. {}", no), "",
          no == 35 ? Verdict::kReproduced : Verdict::kNotReproducible,
          "the pin nearest arccos K1 = 46.3 deg from the line of centres; fixes the mapping of Li's clockwise numbering",
          "ltca backlash cases/li_table1.toml");
  }
  const PinFigures s = AnalyseLi(stated), h = AnalyseLi(hyp);
  const std::string cmd_s = "ltca solve cases/li_table1.toml", cmd_h = "ltca solve cases/li_table1_hypothesis.toml";
  // Li's pattern: 16 pins, No. 24-39 (Fig. 9); the largest force 91.11 N at No. 35. Both decks
  // are held to the same tolerances: pin count within 1 with the same end pins; force within 1 %.
  const auto pins_match = [](const PinFigures& f) {
    return std::abs(f.pins - 16) <= 1 && f.first_no == 24 && f.last_no == 39;
  };
  const auto force_match = [](const PinFigures& f) { return f.max_force_no == 35 && Rel(f.max_force, 91.11) <= 0.01; };
  b.Add("li.stated.pins", "pins in contact, stated inputs (E 2.08e5 MPa, T 57 N*m)", "16 (No. 24-39)",
        fmt::format("{} (No. {}-{})", s.pins, s.first_no, s.last_no), "", Within(pins_match(s), Verdict::kReproduced),
        "pin count within 1, the same end pins; 91 N on a 10 mm steel line contact deforms by ~1 um, not 0.057 mm: "
        "the published pattern needs a contact about 1000 times softer (next rows)",
        cmd_s);
  b.Add("li.stated.max_force", "largest pin force, stated inputs", "91.11 N (No. 35)",
        fmt::format("{:.2f} N (No. {})", s.max_force, s.max_force_no), Percent(s.max_force, 91.11),
        Within(force_match(s), Verdict::kReproduced),
        "force within 1 % at the same pin; few pins share the load when the contacts are steel-stiff", cmd_s);
  b.Add("li.hypothesis.pins", "pins in contact, E entered as 208 MPa and T of one cycloid (28.5 N*m)",
        "16 (No. 24-39)", fmt::format("{} (No. {}-{})", h.pins, h.first_no, h.last_no), "",
        Within(pins_match(h), Verdict::kReproducedConvention), "hypothesis deck; pin count within 1", cmd_h);
  b.Add("li.hypothesis.max_force", "largest pin force and its pin, hypothesis", "91.11 N at No. 35",
        fmt::format("{:.2f} N at No. {}", h.max_force, h.max_force_no), Percent(h.max_force, 91.11),
        Within(force_match(h), Verdict::kReproducedConvention), "hypothesis deck; force within 1 %", cmd_h);
  b.Add("li.hypothesis.max_pressure_pin", "pin of the largest contact pressure, hypothesis", "No. 32",
        fmt::format("No. {}", h.max_pressure_no), "",
        h.max_pressure_no == 32 ? Verdict::kReproducedConvention : Verdict::kNotReproducible, "hypothesis deck", cmd_h);
  b.Add("li.hypothesis.max_deformation", "largest deformation and its pin (Fig. 10), hypothesis", "0.057 mm at No. 35",
        fmt::format("{:.4f} mm at No. {}", h.max_deform, h.max_deform_no), Percent(h.max_deform, 0.057),
        (h.max_deform_no == 35 && Rel(h.max_deform, 0.057) <= 0.10) ? Verdict::kReproducedConvention
                                                                     : Verdict::kNotReproducible,
        "hypothesis deck; within 10 %", cmd_h);
  {
    double worst = 0;
    std::string ours, theirs;
    for (std::size_t k = 0; k < h.listed_half.size(); ++k) {
      worst = std::max(worst, std::abs(h.listed_half[k] - kLiListedHalfWidth[k]));
      ours += fmt::format("{}{:.3f}", k == 0 ? "" : " / ", h.listed_half[k]);
      theirs += fmt::format("{}{:.2f}", k == 0 ? "" : " / ", kLiListedHalfWidth[k]);
    }
    b.Add("li.hypothesis.half_widths", "Hertz half-widths at pins No. 24-27 and 36-39 (Table 2), hypothesis, mm",
          theirs, ours, fmt::format("worst {:.3f} mm", worst),
          worst <= 0.05 ? Verdict::kReproducedConvention : (worst <= 0.1 ? Verdict::kSameOrder : Verdict::kNotReproducible),
          "hypothesis deck; tolerance 0.05 mm per pin. Ours are 9-35 % narrower: under the signed reading of Li eq. 4 "
          "(+- for the concave flank) the half-widths fit within 0.045 mm, but then the force pattern does not (17 pins, "
          "109 N); no single convention reproduces both",
          cmd_h);
  }
  b.Add("li.hypothesis.te", "loaded TE (Fig. 9), hypothesis, at Li's Table 2 position", "-3.80 to -7.46 arcmin",
        fmt::format("{:.2f} arcmin", h.te_arcmin), "",
        (h.te_arcmin <= -3.80 && h.te_arcmin >= -7.46) ? Verdict::kReproducedConvention : Verdict::kNotReproducible,
        "hypothesis deck; inside the published range", cmd_h);
  {
    // Either modulus at the hypothesis' forces would do (both are a stated convention); 1 %, as the forces.
    const bool stated_e = Rel(h.stated_pressure, 603.58) <= 0.01, soft_e = Rel(h.max_pressure, 603.58) <= 0.01;
    b.Add("li.max_pressure_value", "largest contact pressure (Table 2)", "603.58 MPa",
          fmt::format("{:.2f} MPa (hypothesis forces, stated E)", h.stated_pressure),
          Percent(h.stated_pressure, 603.58), Within(stated_e || soft_e, Verdict::kReproducedConvention),
          fmt::format("tolerance 1 % with either modulus; with the hypothesis' soft modulus the pressure is {:.1f} MPa; "
                      "{}",
                      h.max_pressure,
                      stated_e || soft_e ? "Li's 603.58 MPa matches one modulus within 1 %"
                                         : "Li's 603.58 MPa matches neither modulus: the pressure was computed with "
                                           "the real modulus and a different rho or E*"),
          cmd_h);
  }
}

void Jiang(const fs::path& dir, Builder& b) {
  b.paper = "Jiang 2022: Table 2 pair (section 5)";
  const Deck deck = LoadDeck(dir / "jiang2022_table2.toml");
  double lo = INFINITY, hi = -INFINITY;
  int ok = 0;
  const auto names = solvers::SolverNames();
  for (const auto& name : names) {
    const Loaded l = Solve(deck, name);
    ok += l.status == SolverStatus::kSuccess;
    lo = std::min(lo, l.mean_te);
    hi = std::max(hi, l.mean_te);
  }
  b.Add("jiang2022.solved", "Table 2 pair solved by every solver", "(not published)",
        fmt::format("{}/{} success, mean TE {:.4f} arcsec, spread {:.1e} arcsec", ok, names.size(), lo, hi - lo), "",
        ok == static_cast<int>(names.size()) && hi - lo < 1e-5 ? Verdict::kReproduced : Verdict::kFails,
        "the deck takes z_a, z_b, R_b, r_p, e, b, T, E, nu as stated", "ltca compare cases/jiang2022_table2.toml");
  {
    // The pitch radii are e z_b and e z_a, so their ratio is z_b / z_a. Jiang prints them in whole
    // millimetres (30, 27): the printed ratio allows [29.5 / 27.5, 30.5 / 26.5].
    const auto& pair = deck.pair;
    const double r_b = pair.eccentricity * pair.pin_count, r_a = pair.eccentricity * pair.tooth_count;
    const double ratio = r_b / r_a;
    b.Add("jiang2022.pitch_radii", "r_b / r_a (pin / cycloid pitch radii)", fmt::format("30 / 27 = {:.4f}", 30.0 / 27.0),
          fmt::format("z_b / z_a = {} / {} = {:.4f}", pair.pin_count, pair.tooth_count, ratio), "",
          Within(ratio >= 29.5 / 27.5 && ratio <= 30.5 / 26.5, Verdict::kReproduced),
          fmt::format("tolerance: the printed whole millimetres; the pitch radii must be in the ratio of the tooth "
                      "numbers: r_b = e z_b = {:g} mm, r_a = e z_a = {:g} mm",
                      r_b, r_a),
          "ltca geometry cases/jiang2022_table2.toml");
    // lambda_c = r_b / R_b is the curtate coefficient K1 = e z_b / R_b; tolerance half the printed digit.
    const double k1 = pair.CurtateCoefficient();
    b.Add("jiang2022.shortening_factor", "shortening factor lambda_c = r_b / R_b", "0.3",
          fmt::format("e z_b / R_b = {:.2f}", k1), "", Within(std::abs(k1 - 0.3) <= 0.05, Verdict::kReproduced),
          fmt::format("tolerance 0.05; 0.3 = 30 / {:g} uses the table's inconsistent r_b", pair.pin_circle_radius),
          "ltca geometry cases/jiang2022_table2.toml");
    // 72.3321 W lost at 99.9 % efficiency means 72.3 kW in; at T = 100 N*m that is the output
    // speed below, and the crank turns z_a / (z_b - z_a) times faster. The row compares that crank
    // speed with a stated ceiling of 10,000 rpm, above the input speed of any servo motor or
    // cycloid stage catalogue.
    const double input_kw = 72.3321 / (1.0 - 0.999) / 1000.0;
    const double torque = units::NmmToNm(deck.RequireLoad().torque);
    const double output_rad_s = input_kw * 1000 / torque;
    const double crank_rpm = output_rad_s * pair.tooth_count / (pair.pin_count - pair.tooth_count) * 60.0 /
                             (2.0 * units::kPi);
    const double ceiling_rpm = 10000.0;
    b.Add("jiang2022.input_power", "input power implied by the efficiency results (section 5.3)",
          "72.3321 W lost at 99.9 %",
          fmt::format("{:.1f} kW, i.e. {:.0f} rad/s at T = {:g} N*m", input_kw, output_rad_s, torque), "",
          Within(crank_rpm <= ceiling_rpm, Verdict::kReproduced),
          fmt::format("the crank would turn at {:.0f} rpm, above a ceiling of {:.0f} rpm (any servo motor or cycloid "
                      "stage): about 70 kW does not follow from T = {:g} N*m at any speed an RV stage runs at; "
                      "recorded, not used",
                      crank_rpm, ceiling_rpm, torque),
          "");
  }
}


// --- Jiang 2022 section 5.2, Fig. 15, Table 4 (docs/efficiency.md) --------------------------------
struct EfficiencyRun {
  double loss = 0, efficiency = 0, loss_range = 0;  // mean W, energy-weighted, max - min W
  bool ok = false;
};
EfficiencyRun RunEfficiencyDeck(const Deck& deck) {
  SolverOptions o;
  o.name = "bisection";
  // Linearised kinematics, the default (whatever the deck's [solver] names).
  analysis::EfficiencyRunner runner(deck.MakeStage().WithKinematics(contact::ContactKinematics::kLinearised), o,
                          deck.RequireLoad().torque, deck.RequireFriction(), deck.RequireOperation());
  for (const double crank : runner.cranks()) runner.Solve(crank);
  const analysis::EfficiencySummary s = runner.Summary();
  return {s.power_loss.mean, s.efficiency, s.power_loss.max - s.power_loss.min, s.all_succeeded()};
}
double LossAtCrank(const Deck& deck, double crank_deg) {
  SolverOptions o;
  o.name = "bisection";
  analysis::EfficiencyRunner runner(deck.MakeStage({units::DegToRad(crank_deg)}).WithKinematics(contact::ContactKinematics::kLinearised),
                          o, deck.RequireLoad().torque, deck.RequireFriction(), deck.RequireOperation());
  return runner.Solve(units::DegToRad(crank_deg)).power_loss;
}

void JiangEfficiency(const fs::path& dir, Builder& b) {
  b.paper = "Jiang 2022: friction and efficiency (section 5.2, Fig. 15, Table 4)";
  const fs::path path = dir / "jiang2022_table2_efficiency.toml";
  const std::string cmd = "ltca efficiency cases/jiang2022_table2_efficiency.toml";
  const std::string sleeve = "friction.sleeve_bore_radius_mm=7.5";
  const Deck plain = LoadDeck(path);
  const Deck with = LoadDeck(path, {sleeve});
  // t = 10 ms at 20 r/s is 72 deg of crank.
  const double l0 = LossAtCrank(plain, 0.0), l10 = LossAtCrank(plain, 72.0);
  const double s0 = LossAtCrank(with, 0.0), s10 = LossAtCrank(with, 72.0);
  const EfficiencyRun a = RunEfficiencyDeck(plain), w = RunEfficiencyDeck(with);
  // "Same order" is a factor of 2 either way at most, as for liu2021.t1.pp_te (a factor of
  // 3 is not the same order).
  const auto within_two = [](double ours, double published) { return ours > published / 2 && ours < published * 2; };
  b.Add("jiang2022.s52.loss", "mixed-lubrication power loss without sleeve, 20 r/s, Ra 0.3 um (Fig. 13)",
        "72.3321 W (t = 0), 35.9208 W (t = 10 ms)",
        fmt::format("{:.2f} W (crank 0), {:.2f} W (crank 72 deg); mean over a mesh period {:.2f} W", l0, l10, a.loss),
        fmt::format("{} at t = 0; {:.2f} x Jiang's at t = 10 ms", Percent(l0, 72.3321), l10 / 35.9208),
        Within(within_two(l0, 72.3321) && within_two(l10, 35.9208), Verdict::kSameOrder),
        fmt::format("'same order' needs a factor 2 or less at both instants: at t = 0 within a few %, but Jiang's loss "
                    "halves within 10 ms while ours varies by about 2 % over the mesh period (no transient start-up in "
                    "a quasi-static model), so at t = 10 ms ours is {:.2f} times his. Left open by the paper: the "
                    "speed's meaning (20 r/s read as crank revolutions), the load distribution (his eq. 11 with "
                    "clearances vs our solved forces), the composite roughness and the film constant "
                    "(docs/efficiency.md)",
                    l10 / 35.9208),
        cmd);
  b.Add("jiang2022.s52.loss_sleeve", "power loss with the pin sleeve (Fig. 13)", "27.2156 W (t = 0), 16.9709 W (t = 10 ms)",
        fmt::format("{:.2f} W (crank 0), {:.2f} W (crank 72 deg), bore / sleeve radius 7.5 / 10 (chosen)", s0, s10),
        Percent(s0, 27.2156), Verdict::kNotReproducible,
        fmt::format("Jiang gives no sleeve radii; eq. 34 scales the loss by r_bore / r_sleeve, so his {:.3f} at t = 0 "
                    "implies a ratio near that (with the same coefficient); ours uses the chosen 0.75",
                    27.2156 / 72.3321),
        cmd + " --set " + sleeve);
  b.Add("jiang2022.s52.efficiency", "meshing efficiency without / with sleeve (Fig. 13)", "99.9 % / 99.96 %",
        fmt::format("{:.2f} % / {:.2f} %", 100 * a.efficiency, 100 * w.efficiency), "", Verdict::kNotReproducible,
        fmt::format("P_out = T omega_c = 100 N*m x 2 pi 20 / 23 rad/s = {:.0f} W: a loss of about 72 W cannot be 0.1 % "
                    "of the input (see jiang2022.input_power)",
                    100.0 * 2 * units::kPi * 20 / 23),
        cmd);
  // Fig. 15: 10 .. 40 r/s.
  std::vector<double> losses, efficiencies;
  for (const int rps : {10, 20, 30, 40}) {
    const Deck d = LoadDeck(path, {fmt::format("operation.input_speed_rpm={}", rps * 60)});
    const EfficiencyRun run = RunEfficiencyDeck(d);
    losses.push_back(run.loss);
    efficiencies.push_back(run.efficiency);
  }
  b.Add("jiang2022.fig15.speed", "power loss without sleeve at 10 / 20 / 30 / 40 r/s (Fig. 15)", "23.6 W .. 119 W",
        fmt::format("{:.1f} / {:.1f} / {:.1f} / {:.1f} W", losses[0], losses[1], losses[2], losses[3]),
        fmt::format("{:.2f} x at 10 r/s, {:.2f} x at 40 r/s; 40 / 10 r/s: {:.2f} (published {:.2f})", losses[0] / 23.6,
                    losses[3] / 119.0, losses[3] / losses[0], 119.0 / 23.6),
        Within(within_two(losses[0], 23.6) && within_two(losses[3], 119.0), Verdict::kSameOrder),
        "'same order' needs a factor 2 or less at both ends; ours grows less than in proportion to the speed (the mixed "
        "coefficient falls as the film thickens; most contacts stay boundary-dominated, lambda < 1), Jiang's more "
        "than in proportion (see jiang2022.claim.efficiency_speed)",
        cmd + " --set operation.input_speed_rpm=600 (1200, 1800, 2400)");
  b.Add("jiang2022.claim.speed", "the loss rises with speed (Fig. 15)", "rises",
        fmt::format("{:.1f} < {:.1f} < {:.1f} < {:.1f} W", losses[0], losses[1], losses[2], losses[3]), "",
        losses[0] < losses[1] && losses[1] < losses[2] && losses[2] < losses[3] ? Verdict::kHolds : Verdict::kFails, "",
        cmd + " --set operation.input_speed_rpm=600 (1200, 1800, 2400)");
  // Fig. 15 (a): "The transmission efficiency decreased from 99.97% to 99.84% as the speed
  // increased without the pin tooth sleeve". The claim is the direction: it holds only if ours
  // falls at every step of speed too (ours rises).
  const bool falls = efficiencies[0] > efficiencies[1] && efficiencies[1] > efficiencies[2] && efficiencies[2] > efficiencies[3];
  const bool rises = efficiencies[0] < efficiencies[1] && efficiencies[1] < efficiencies[2] && efficiencies[2] < efficiencies[3];
  b.Add("jiang2022.claim.efficiency_speed", "the efficiency without sleeve falls with speed, 10 -> 40 r/s (Fig. 15)",
        "falls, 99.97 % -> 99.84 %",
        fmt::format("{}: {:.2f} / {:.2f} / {:.2f} / {:.2f} %", falls ? "falls" : (rises ? "rises" : "not monotone"),
                    100 * efficiencies[0], 100 * efficiencies[1], 100 * efficiencies[2], 100 * efficiencies[3]),
        "", falls ? Verdict::kHolds : Verdict::kFails,
        fmt::format("the direction is compared: the output power grows in proportion to the speed; our loss grows "
                    "less ({:.2f} x from 10 to 40 r/s), so our efficiency rises; Jiang's loss grows more ({:.2f} x) "
                    "and his falls",
                    losses[3] / losses[0], 119.0 / 23.6),
        cmd + " --set operation.input_speed_rpm=600 (1200, 1800, 2400)");
  b.Add("jiang2022.claim.sleeve", "the sleeve lowers the loss and its fluctuation (Fig. 13-14)", "lower, smoother",
        fmt::format("mean {:.2f} -> {:.2f} W, range over the mesh period {:.3f} -> {:.3f} W", a.loss, w.loss, a.loss_range,
                    w.loss_range),
        "", w.loss < a.loss && w.loss_range < a.loss_range ? Verdict::kHolds : Verdict::kFails,
        "by construction of eq. 34 with the same coefficient at the bore: every contact's loss scales by r_bore / "
        "r_sleeve < 1, the mean and the range alike",
        cmd + " --set " + sleeve);
  std::vector<double> rough;
  for (const double ra : {0.2, 0.3, 0.4, 0.5}) {
    const Deck d = LoadDeck(path, {fmt::format("operation.roughness_ra_cycloid_um={}", ra),
                                   fmt::format("operation.roughness_ra_pin_um={}", ra)});
    rough.push_back(RunEfficiencyDeck(d).loss);
  }
  const double spread = (*std::max_element(rough.begin(), rough.end()) - *std::min_element(rough.begin(), rough.end())) /
                        rough[1];
  b.Add("jiang2022.claim.roughness", "roughness Ra 0.2 .. 0.5 um matters little (Table 4: 121.8 .. 113.0 W)",
        "little (7 % spread)",
        fmt::format("{:.1f} / {:.1f} / {:.1f} / {:.1f} W, spread {:.1f} % of the Ra 0.3 loss", rough[0], rough[1], rough[2],
                    rough[3], 100 * spread),
        "", spread < 0.1 ? Verdict::kHolds : Verdict::kFails,
        "little: a spread below 10 % of the loss; the loss rises with Ra (a thinner film ratio); Jiang's falls",
        cmd + " --set operation.roughness_ra_cycloid_um=0.2 --set operation.roughness_ra_pin_um=0.2 (0.3, 0.4, 0.5)");
}
// --- end of Jiang 2022 section 5.2 ----------------------------------------------------------------
}  // namespace

const char* ToString(Verdict verdict) {
  switch (verdict) {
    case Verdict::kReproduced: return "reproduced";
    case Verdict::kReproducedInexact: return "reproduced (printed value inexact)";
    case Verdict::kReproducedConvention: return "reproduced under a stated convention";
    case Verdict::kSameOrder: return "same order, not reproducible exactly";
    case Verdict::kNotReproducible: return "not reproducible";
    case Verdict::kHolds: return "claim holds";
    case Verdict::kFails: return "claim fails";
  }
  return "?";
}

ValidationReport Validate(const fs::path& cases_dir) {
  Builder b;
  ValidationReport report;
  Chen(cases_dir, b);
  LiuGeometryAndLoaded(cases_dir, b);
  LiuErrorSurfaces(cases_dir, b);
  report.liu_table2 = LiuTable2(cases_dir, b);
  {
    // Slice-count convergence: Liu 5.3's phi = 0.02 deg over one revolution in 37
    // positions, compatibility, linearised; 200 slices is the reference.
    Deck phi = LoadDeck(cases_dir / "liu2021_sec53_phi.toml");
    phi.sweep.positions = 37;
    SolverOptions options = phi.solver;
    options.name = "compatibility";
    report.slice_convergence =
        RunSliceStudy(phi, phi.sweep.CrankAngles(), phi.RequireLoad().torque, options, {5, 10, 20, 50, 100, 200}, 1);
    report.slice_face_edge = FaceEdgeUnloaded(phi, phi.sweep.CrankAngles());
  }
  Li(cases_dir, b);
  Jiang(cases_dir, b);
  JiangEfficiency(cases_dir, b);
  report.rows = std::move(b.rows);
  return report;
}

std::string ToMarkdown(const ValidationReport& report) {
  std::ostringstream os;
  std::string paper;
  for (const auto& r : report.rows) {
    if (r.paper != paper) {
      paper = r.paper;
      os << "\n### " << paper << "\n\n"
         << "| id | quantity | published | ours | difference | verdict | why / convention | command |\n"
         << "|---|---|---|---|---|---|---|---|\n";
    }
    os << fmt::format("| `{}` | {} | {} | {} | {} | **{}** | {} | {} |\n", r.id, r.quantity, r.published, r.ours,
                      r.difference, ToString(r.verdict), r.note, r.command.empty() ? "" : "`" + r.command + "`");
  }
  os << "\n### Liu 2021 Table 2, computed (the paper plots these in Fig. 8)\n\n"
     << "Absolute rho, linearised bisection for the loaded figures, exact unloaded TCA for the backlash; one mesh "
        "period in 91 positions.\n\n"
     << "| case | dR_rp (um) | dR_p (um) | mean TE (arcsec) | pp TE (arcsec) | mean backlash (arcsec) | pp backlash "
        "(arcsec) | mean pins | max stress (MPa) |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& t : report.liu_table2) {
    os << fmt::format("| {} | {:+g} | {:+g} | {:.3f} | {:.4f} | {:.3f} | {:.4f} | {:.2f} | {:.1f} |\n", t.case_number,
                      t.d_rrp_um, t.d_rp_um, t.mean_te_arcsec, t.pp_te_arcsec, t.mean_backlash_arcsec,
                      t.pp_backlash_arcsec, t.mean_pins, t.max_stress_mpa);
  }
  if (!report.slice_convergence.empty()) {
    const analysis::SliceStudyRow& ref = report.slice_convergence.back();
    os << "\n### Slice-count convergence under misalignment\n\n"
       << "Liu 2021 section 5.3, phi = 0.02 deg (`cases/liu2021_sec53_phi.toml`, 37 positions over one revolution), "
          "linearised kinematics, compatibility. The PPTE's error is against " << ref.slices << " slices; the "
          "backlash's against the face-edge value, the first contact of two plane models with the cycloid centre where "
          "the tilted axis puts it at each face (" << fmt::format("{:.4f} / {:.4f} arcsec", report.slice_face_edge.mean_arcsec,
                                                                   report.slice_face_edge.pp_arcsec)
       << ", `analysis::FaceEdgeUnloaded`): the unloaded analysis seeks the first contact at the face edges, so it does not "
          "depend on the slice count (docs/contact.md). Times: docs/performance.md.\n\n"
       << "| slices | PPTE (arcsec) | error | mean backlash (arcsec) | error | pp backlash (arcsec) | error |\n"
          "|---|---|---|---|---|---|---|\n";
    for (const auto& r : report.slice_convergence) {
      os << fmt::format("| {} | {:.4f} | {:.1e} | {:.4f} | {:.1e} | {:.4f} | {:.1e} |\n", r.slices, r.pp_te_arcsec,
                        std::abs(r.pp_te_arcsec - ref.pp_te_arcsec), r.mean_backlash_arcsec,
                        std::abs(r.mean_backlash_arcsec - report.slice_face_edge.mean_arcsec), r.pp_backlash_arcsec,
                        std::abs(r.pp_backlash_arcsec - report.slice_face_edge.pp_arcsec));
    }
  }
  return os.str();
}

}  // namespace ltca::app
