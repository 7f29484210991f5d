// Issue 16: the figure module (ltca/app/plots.hpp); the bench chart drawn with it is tested in
// tests/benchmarks. The figures
// of the commands are checked for every deck by tests/app/check_svg.py.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <doctest/doctest.h>

#include "helpers.hpp"
#include "ltca/app/modules.hpp"
#include "ltca/app/plots.hpp"

namespace {

namespace plots = ltca::app::plots;
namespace fs = std::filesystem;

using ltca::test::CheckSvg;

plots::Figure TwoPanels() {
  plots::Figure f;
  f.title = "a & b <case> #1: crank 0 to 9 deg";
  f.caption = "deck: x.toml\nsecond line";
  f.columns = 2;
  for (int k = 0; k < 2; ++k) {
    plots::Panel p;
    p.x_label = "crank angle (deg)";
    p.y_label = k == 0 ? "TE (arcsec)" : "pin force (N)";
    p.series.push_back({"first #a", {0, 1, 2}, {1, 2, 3}, plots::Style::kLineMarkers});
    p.series.push_back({"second & b", {0, 1, 2}, {3, 2, 1}, k == 0 ? plots::Style::kLine : plots::Style::kBars});
    p.series.push_back({"", {0, 2}, {2, 2}, plots::Style::kLine});  // unlabelled: not in the legend
    p.marks.push_back({plots::Mark::Axis::kHorizontal, 2.0, "mean 2", false});
    f.panels.push_back(p);
  }
  return f;
}

// The cairo devices (PNG, PDF) leave fontconfig's caches allocated at exit, which LeakSanitizer
// reports as leaks of the whole test process: under AddressSanitizer (the debug preset) the PNG
// and PDF test is skipped; SVG (PLplot's own device) is tested everywhere.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kUnderAsan = true;
#else
constexpr bool kUnderAsan = false;
#endif

}  // namespace

TEST_CASE("app: a figure is an SVG whose panels, axis labels and labelled series an XML parser reads, escapes and all") {
  const fs::path svg = fs::temp_directory_path() / "ltca_plots_test_two_panels.svg";
  {
    std::ofstream os(svg, std::ios::binary);
    plots::Write(TwoPanels(), os);
  }
  CHECK(CheckSvg(svg, 2, 2) == 0);
  CHECK(CheckSvg(svg, 2, 3) != 0);  // the check can fail: the unlabelled series is not counted
  fs::remove(svg);
}

TEST_CASE("app: figures drawn from several threads at once are each whole (PLplot is serialised)") {
  std::vector<std::string> out(4);
  std::vector<std::thread> threads;
  for (auto& o : out) {
    threads.emplace_back([&o] {
      std::ostringstream os;
      plots::Write(TwoPanels(), os);
      o = os.str();
    });
  }
  for (auto& t : threads) t.join();
  for (const auto& o : out) {
    CHECK(o.rfind("<?xml", 0) == 0);
    CHECK(o.find("</svg>") != std::string::npos);
    CHECK(o == out.front());  // the same figure, byte for byte
  }
}

TEST_CASE("app: --svg FILE.png and FILE.pdf draw PNG and PDF (plplot-driver-cairo)" * doctest::skip(kUnderAsan)) {
  CHECK(plots::FormatForPath("a/b.png") == plots::Format::kPng);
  CHECK(plots::FormatForPath("b.pdf") == plots::Format::kPdf);
  CHECK(plots::FormatForPath("-") == plots::Format::kSvg);
  CHECK(plots::FormatForPath("b.svg") == plots::Format::kSvg);
  std::ostringstream png, pdf;
  plots::Write(TwoPanels(), png, plots::Format::kPng);
  plots::Write(TwoPanels(), pdf, plots::Format::kPdf);
  CHECK(png.str().rfind("\x89PNG", 0) == 0);
  CHECK(pdf.str().rfind("%PDF", 0) == 0);
}


TEST_CASE("app: a module that is not there is a runtime error naming it and where it was looked for (issue 54)") {
  // The modules (ltca/app/modules.hpp): the figures' own is found in the build tree and has its
  // entry points; one that does not exist is refused with its file name and the folders searched.
  CHECK(ltca::app::ModuleSymbol("plots", "ltca_plots_draw") != nullptr);
  try {
    ltca::app::ModuleSymbol("no_such_part", "entry");
    FAIL("a missing module loaded");
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    CHECK(what.find("ltca_no_such_part.so") != std::string::npos);
    CHECK(what.find("looked in") != std::string::npos);
  }
  CHECK_THROWS_AS(ltca::app::ModuleSymbol("plots", "no_such_entry"), std::runtime_error);
}
