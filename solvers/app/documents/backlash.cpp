#include "documents/backlash.hpp"

#include <cmath>

#include <fmt/format.h>

#include "documents/common.hpp"
#include "ltca/geometry/units.hpp"

namespace ltca::app::documents {
namespace {

using units::RadToArcsec;
using units::RadToDeg;

/// The angles of a position, rad: NaN where it failed.
struct Angles {
  double c1, c2, backlash;
};
Angles AnglesOf(const analysis::BacklashPosition& p) {
  const contact::UnloadedContact& r = p.contact;
  return p.ok ? Angles{r.theta_c1, r.theta_c2, r.backlash} : Angles{NAN, NAN, NAN};
}

}  // namespace

nlohmann::json BacklashHead(const Deck& deck, contact::ContactKinematics kinematics) {
  return {{"case", CaseJson(deck)}, {"model", ModelJson(deck.Model())}, {"kinematics", contact::ToString(kinematics)}};
}

nlohmann::json Json(const analysis::BacklashPosition& p, bool two_discs) {
  const contact::UnloadedContact& r = p.contact;
  const Angles a = AnglesOf(p);
  nlohmann::json clearance = nlohmann::json::array(), after = nlohmann::json::array();
  for (const double c : r.clearance) clearance.push_back(FiniteOrNull(units::MmToUm(c)));
  for (const double c : r.clearance_at_c1) after.push_back(p.ok ? FiniteOrNull(units::MmToUm(c)) : nlohmann::json(nullptr));
  const auto pin_or_null = [&](int pin) { return p.ok ? nlohmann::json(pin + 1) : nlohmann::json(nullptr); };
  nlohmann::json position = {{"crank_deg", RadToDeg(r.crank)},
                             {"status", ToString(p.ok ? analysis::RunStatus::kSuccess : analysis::RunStatus::kFailed)},
                             {"theta_c1_arcsec", FiniteOrNull(RadToArcsec(a.c1))},
                             {"theta_c2_arcsec", FiniteOrNull(RadToArcsec(a.c2))},
                             {"backlash_arcsec", FiniteOrNull(RadToArcsec(a.backlash))},
                             {"first_contact_pin", pin_or_null(r.first_pin_c1)},
                             {"first_contact_pin_reverse", pin_or_null(r.first_pin_c2)},
                             {"clearance_um", clearance},
                             {"clearance_at_first_contact_um", after},
                             {"interference_arcsec", p.ok ? FiniteOrNull(RadToArcsec(r.interference)) : nlohmann::json(nullptr)},
                             {"unload_torque_nm", FiniteOrNull(units::NmmToNm(p.unload_torque_nmm))},
                             {"unload_torque_reverse_nm", FiniteOrNull(units::NmmToNm(p.unload_torque_reverse_nmm))}};
  if (!p.ok) position["message"] = p.failure;
  if (two_discs) {
    position["first_contact_disc"] = p.ok ? nlohmann::json(p.disc_c1) : nlohmann::json(nullptr);
    position["first_contact_disc_reverse"] = p.ok ? nlohmann::json(p.disc_c2) : nlohmann::json(nullptr);
    nlohmann::json second = nlohmann::json::array();
    for (const double c : p.second_clearance) second.push_back(FiniteOrNull(units::MmToUm(c)));
    position["second_disc_clearance_um"] = second;
    // Each disc's own first contact is not the stage's: no figure rather than a misleading one.
    position["clearance_at_first_contact_um"] = nullptr;
  }
  return position;
}

Table Columns(const std::vector<analysis::BacklashPosition>& positions, bool two_discs) {
  Table t;
  const auto um = [](const std::vector<double>& mm, bool ok) {
    std::vector<double> v;
    for (const double c : mm) v.push_back(ok ? units::MmToUm(c) : NAN);
    return v;
  };
  for (const analysis::BacklashPosition& p : positions) {
    const contact::UnloadedContact& r = p.contact;
    const Angles a = AnglesOf(p);
    t.Add("crank_deg", RadToDeg(r.crank));
    t.Add("theta_c1_arcsec", RadToArcsec(a.c1));
    t.Add("theta_c2_arcsec", RadToArcsec(a.c2));
    t.Add("backlash_arcsec", RadToArcsec(a.backlash));
    t.Add("first_contact_pin", p.ok ? r.first_pin_c1 + 1.0 : NAN);
    t.Add("first_contact_pin_reverse", p.ok ? r.first_pin_c2 + 1.0 : NAN);
    t.Add("clearance_um", um(r.clearance, true));
    t.Add("interference_arcsec", p.ok ? RadToArcsec(r.interference) : NAN);
    t.Add("unload_torque_nm", units::NmmToNm(p.unload_torque_nmm));
    t.Add("unload_torque_reverse_nm", units::NmmToNm(p.unload_torque_reverse_nmm));
    if (two_discs) {
      t.Add("first_contact_disc", p.ok ? p.disc_c1 : NAN);
      t.Add("first_contact_disc_reverse", p.ok ? p.disc_c2 : NAN);
      t.Add("second_disc_clearance_um", um(p.second_clearance, true));
      t.Add("clearance_at_first_contact_um", NAN);  // null in the document: not the stage's figure
    } else {
      t.Add("clearance_at_first_contact_um", um(r.clearance_at_c1, p.ok));
    }
  }
  return t;
}

nlohmann::json Json(const Deck& deck, const analysis::BacklashResult& result) {
  const analysis::BacklashSummary& s = result.summary;
  nlohmann::json summary = {{"mean_backlash_arcsec", FiniteOrNull(RadToArcsec(s.mean()))},
                            {"pp_backlash_arcsec", FiniteOrNull(RadToArcsec(s.pp()))},
                            {"status", ToString(s.failed() == 0 ? analysis::RunStatus::kSuccess : analysis::RunStatus::kFailed)},
                            {"positions", result.positions},
                            {"succeeded_positions", s.succeeded()},
                            {"failed_positions", s.failed()},
                            {"closed_period", result.closed_period},
                            {"preloaded_positions", s.preloaded()},
                            {"max_interference_arcsec", s.preloaded() > 0 ? nlohmann::json(RadToArcsec(s.max_interference()))
                                                                          : nlohmann::json(0.0)},
                            {"min_unload_torque_nm", FiniteOrNull(units::NmmToNm(s.min_unload_torque()))}};
  if (deck.reducer) summary["scope"] = "the pin ring's mesh alone; the stage's free play is the backlash of ltca stiffness";
  if (s.failed() > 0) summary["first_failure"] = s.first_failure();
  if (!result.notes.empty()) summary["notes"] = result.notes;
  return summary;
}

nlohmann::json Json(const Deck& deck, const std::vector<analysis::BacklashPosition>& positions,
                    const analysis::BacklashResult& result) {
  nlohmann::json doc = BacklashHead(deck, result.kinematics);
  nlohmann::json list = nlohmann::json::array();
  for (const analysis::BacklashPosition& p : positions) list.push_back(Json(p, result.discs == 2));
  doc["positions"] = std::move(list);
  doc["summary"] = Json(deck, result);
  return doc;
}

BacklashJsonWriter::BacklashJsonWriter(std::ostream& os, const Deck& deck, contact::ContactKinematics kinematics, bool two_discs)
    : os_(os), two_discs_(two_discs) {
  const nlohmann::json head = BacklashHead(deck, kinematics);
  os_ << "{\n\"case\": " << Dump(head.at("case"), -1) << ",\n\"model\": " << Dump(head.at("model"), -1)
      << ",\n\"kinematics\": " << Dump(head.at("kinematics"), -1) << ",\n\"positions\": [";
}

void BacklashJsonWriter::Add(const analysis::BacklashPosition& p) {
  os_ << (written_++ == 0 ? "\n" : ",\n") << Dump(Json(p, two_discs_), -1);
}

void BacklashJsonWriter::Finish(const Deck& deck, const analysis::BacklashResult& result) {
  os_ << "\n],\n\"summary\": " << Dump(Json(deck, result), -1) << "\n}\n";
}

std::string BacklashTextHead(const Deck& deck, const analysis::Stage& stage, contact::ContactKinematics kinematics) {
  std::string text = CaseLines(deck) + ModelLine(deck);
  text += fmt::format("unloaded TCA, {} kinematics, {} positions from {:g} to {:g} deg crank\n", contact::ToString(kinematics),
                      stage.cranks().size(), RadToDeg(deck.sweep.crank_start), RadToDeg(deck.sweep.crank_end));
  if (stage.model().slice_count() > 1) {
    text += fmt::format("first contact sought at both face edges and the {} slice centres\n", stage.model().slice_count());
  }
  if (stage.disc_count() == 2) {
    text += "two discs: the stage's free play, on each flank the nearer first contact of either disc (pin column: disc:pin)\n";
  }
  return text + fmt::format("{:>10} {:>14} {:>14} {:>14} {:>6}\n", "crank_deg", "theta_c1_as", "theta_c2_as", "backlash_as", "pin");
}

std::string Text(const analysis::BacklashPosition& p, bool two_discs) {
  const Angles a = AnglesOf(p);
  const std::string pin = !p.ok ? "n/a" : two_discs ? fmt::format("{}:{}", p.disc_c1, p.contact.first_pin_c1 + 1)
                                                    : fmt::format("{}", p.contact.first_pin_c1 + 1);
  return fmt::format("{:>10.4f} {:>14} {:>14} {:>14} {:>6}\n", RadToDeg(p.contact.crank), FormatOrNa(RadToArcsec(a.c1), 4),
                     FormatOrNa(RadToArcsec(a.c2), 4), FormatOrNa(RadToArcsec(a.backlash), 4), pin);
}

std::string Text(const Deck& deck, const analysis::BacklashResult& result) {
  const analysis::BacklashSummary& s = result.summary;
  std::string text;
  if (s.failed() > 0) text += fmt::format("failed                  {} of {} positions, first at {}\n", s.failed(), result.positions, s.first_failure());
  text += fmt::format("mean backlash           {} arcsec   (Liu eq. 17){}\n", FormatOrNa(RadToArcsec(s.mean()), 4),
                      result.closed_period ? "; the last position repeats the first: counted once" : "");
  for (const std::string& note : result.notes) text += fmt::format("note                    {}\n", note);
  if (deck.reducer) {
    text += "note                    the pin ring's mesh alone; the stage's free play (holes, bearings too) is the "
            "backlash of ltca stiffness\n";
  }
  return text + fmt::format("peak-to-peak backlash   {} arcsec\n", FormatOrNa(RadToArcsec(s.pp()), 4));
}

std::string BacklashCsvHead() {
  return "crank_deg,theta_c1_arcsec,theta_c2_arcsec,backlash_arcsec,first_contact_disc,first_contact_pin,status\n";
}

std::string Csv(const analysis::BacklashPosition& p) {
  const contact::UnloadedContact& r = p.contact;
  if (!p.ok) return fmt::format("{:.9g},,,,,,failed\n", RadToDeg(r.crank));
  return fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{},{},success\n", RadToDeg(r.crank), RadToArcsec(r.theta_c1),
                     RadToArcsec(r.theta_c2), RadToArcsec(r.backlash), p.disc_c1, r.first_pin_c1 + 1);
}

BacklashSeries::BacklashSeries(std::size_t positions)
    : backlash_(static_cast<std::int64_t>(positions)), c1_(static_cast<std::int64_t>(positions)), c2_(static_cast<std::int64_t>(positions)) {}

void BacklashSeries::Add(const analysis::BacklashPosition& p) {
  const Angles a = AnglesOf(p);
  const double crank = RadToDeg(p.contact.crank);
  backlash_.Add(added_, crank, RadToArcsec(a.backlash));
  c1_.Add(added_, crank, RadToArcsec(a.c1));
  c2_.Add(added_, crank, RadToArcsec(a.c2));
  ++added_;
}

plots::Figure Figure(const Deck& deck, BacklashSeries& series, const analysis::BacklashResult& result) {
  const std::vector<double>& crank = series.backlash().x();
  plots::Figure figure;
  figure.title = fmt::format("{}: unloaded backlash over crank {:.4g} to {:.4g} deg", CaseTitle(deck),
                             crank.empty() ? 0.0 : crank.front(), crank.empty() ? 0.0 : crank.back());
  const std::string decimated =
      series.backlash().stride() > 1
          ? fmt::format("; drawn: the least and largest of each {} positions", series.backlash().stride())
          : std::string();
  figure.caption = FigureCaption(deck, fmt::format("unloaded TCA, {} kinematics, {} positions; backlash = theta_c1 - theta_c2 "
                                                   "(Liu eq. 17), the first contacts on the drive and coast flanks{}{}",
                                                   contact::ToString(result.kinematics), series.added(),
                                                   result.discs == 2 ? "; two discs: the nearer of either disc's" : "", decimated));
  figure.columns = 2;
  figure.width = 1400;
  figure.height = 520;
  plots::Panel b;
  b.title = "backlash";
  b.x_label = "crank angle (deg)";
  b.y_label = "backlash (arcsec)";
  b.series.push_back({"backlash", crank, series.backlash().y(), plots::Style::kLineMarkers});
  // The sweep's own mean (the repeated state of a closed period once), not the drawn points'.
  MarkMeanAndPeakToPeak(b, series.backlash().y(), "arcsec",
                        series.backlash().stride() > 1 ? RadToArcsec(result.summary.mean()) : NAN);
  figure.panels.push_back(std::move(b));
  plots::Panel r;
  r.title = "rotation of the output to first contact";
  r.x_label = "crank angle (deg)";
  r.y_label = "rotation to first contact (arcsec)";
  r.legend = plots::LegendPlace::kOutsideRight;
  r.series.push_back({"theta_c1 (drive)", series.theta_c1().x(), series.theta_c1().y(), plots::Style::kLineMarkers});
  r.series.push_back({"theta_c2 (coast)", series.theta_c2().x(), series.theta_c2().y(), plots::Style::kLineMarkers});
  r.marks.push_back({plots::Mark::Axis::kHorizontal, 0.0, "", false});
  figure.panels.push_back(std::move(r));
  return figure;
}

}  // namespace ltca::app::documents
