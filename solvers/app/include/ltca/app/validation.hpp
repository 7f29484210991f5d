#pragma once
// The published-number regression: every checkable number of the four papers, computed from the
// decks in cases/, with a verdict. `ltca validate --markdown` writes it into docs/validation.md;
// tests/app/validation_test.cpp fails when a verdict changes or the document is stale.
#include <filesystem>
#include <string>
#include <vector>

#include "ltca/app/deck.hpp"

namespace ltca::app {

enum class Verdict {
  kReproduced,           ///< within the stated tolerance
  kReproducedInexact,    ///< within tolerance of a printed value that is rounded or inexact
  kReproducedConvention, ///< reproduced only under a stated convention or hypothesis
  kSameOrder,            ///< same order of magnitude; depends on something the paper leaves open
  kNotReproducible,      ///< cannot follow from the stated inputs; the note says why
  kHolds,                ///< a qualitative claim that our results confirm
  kFails,                ///< a qualitative claim that our results contradict
};
const char* ToString(Verdict verdict);

struct ValidationRow {
  std::string id;          ///< stable key, e.g. "liu2021.t1.mean_te.absolute"
  std::string paper;       ///< section heading
  std::string quantity;
  std::string published;
  std::string ours;
  std::string difference;
  Verdict verdict = Verdict::kNotReproducible;
  std::string note;        ///< the reason, for anything but kReproduced
  std::string command;     ///< regenerates `ours`
};

/// Liu 2021 Table 2 as computed (the paper gives plots only).
struct LiuTable2Row {
  int case_number = 0;
  double d_rrp_um = 0, d_rp_um = 0;
  double mean_te_arcsec = 0, pp_te_arcsec = 0, mean_backlash_arcsec = 0, pp_backlash_arcsec = 0;
  double mean_pins = 0, max_stress_mpa = 0;
};

struct ValidationReport {
  std::vector<ValidationRow> rows;
  std::vector<LiuTable2Row> liu_table2;
  /// The slice-count convergence under misalignment (times are in the bench).
  std::vector<analysis::SliceStudyRow> slice_convergence;
  /// Its backlash reference: the face-edge value.
  analysis::FaceEdgeBacklash slice_face_edge;
};

/// Computes every row from the decks under cases_dir.
ValidationReport Validate(const std::filesystem::path& cases_dir);

/// The generated part of docs/validation.md.
std::string ToMarkdown(const ValidationReport& report);

}  // namespace ltca::app
