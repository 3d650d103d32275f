// arcs plot / render / report end to end: the quickstart experiment (fewer
// grid sizes) with --save-outputs, its figures and renders, and the HTML
// report loaded in headless Chromium, which must load every image
// (naturalWidth > 0, marked by the page's own check script). Skips with the
// reason when python3-matplotlib or chromium is missing.
#include "tests/e2e/e2e_util.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>

namespace arcs::testing {
namespace {

namespace fs = std::filesystem;

std::string Python() {
  if (const char* p = std::getenv("ARCS_PYTHON")) return p;
  return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

bool HaveMatplotlib() { return RunCmd(Python() + " -c 'import matplotlib, numpy'").code == 0; }

std::string Chromium() {
  for (const char* c : {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"})
    if (fs::exists(c)) return c;
  return "";
}

bool StartsWith(const fs::path& p, const std::string& magic) {
  const std::string s = ReadFile(p);
  return s.size() > magic.size() && s.compare(0, magic.size(), magic) == 0;
}

class ReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!HaveMatplotlib()) GTEST_SKIP() << "python3-matplotlib / python3-numpy not installed (scripts/install_deps.sh)";
  }
};

// The quickstart (MC and RFTA on the built-in shapes, two grid sizes) with --save-outputs.
fs::path RunQuickstart(const fs::path& dir) {
  const CmdResult run = RunCmd(Arcs() + " run '" ARCS_SOURCE_DIR "/experiments/quickstart.yaml' --quiet "
                               "--save-outputs --set 'inputs.grid.sdf_grid.n=[10,14]' --out '" +
                               (dir / "qs").string() + "'");
  EXPECT_EQ(run.code, 0) << run.output;
  return dir / "qs";
}

TEST_F(ReportTest, QuickstartFiguresAndReportLoadInHeadlessChromium) {
  const fs::path dir = TempDir("report_quickstart");
  const fs::path qs = RunQuickstart(dir), out = dir / "figs";
  ASSERT_FALSE(::testing::Test::HasFailure());
  const CmdResult r = RunCmd(Arcs() + " plot '" + qs.string() + "' --out '" + out.string() + "'");
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* f : {"runtime", "scatter", "ablation"}) {
    EXPECT_TRUE(StartsWith(out / (std::string(f) + ".png"), "\x89PNG")) << f << "\n" << r.output;
    EXPECT_TRUE(StartsWith(out / (std::string(f) + ".pdf"), "%PDF")) << f;
  }
  // The quickstart has no voxelizer: that figure is skipped with its reason.
  EXPECT_NE(r.output.find("skipped figure voxel"), std::string::npos) << r.output;
  const CmdResult bad = RunCmd(Arcs() + " plot '" + qs.string() + "' --figure nonsense");
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.output.find("unknown figure 'nonsense'"), std::string::npos) << bad.output;
  const CmdResult missing = RunCmd(Arcs() + " report '" + (dir / "nowhere").string() + "'");
  EXPECT_NE(missing.code, 0);
  EXPECT_NE(missing.output.find("no results file"), std::string::npos) << missing.output;

  // The report: tables, figures and renders in one self-contained page.
  const CmdResult rep = RunCmd(Arcs() + " report '" + qs.string() + "'");
  ASSERT_EQ(rep.code, 0) << rep.output;
  const std::string page = ReadFile(qs / "report.html");
  // The figures named by the issue and one render row per shape and grid size
  // (4 shapes x 2 sizes), each with the reference and both methods.
  for (const char* f : {"alt='figure runtime'", "alt='figure scatter'", "alt='figure ablation'"})
    EXPECT_NE(page.find(f), std::string::npos) << f;
  std::size_t renders = 0;
  for (std::size_t p = 0; (p = page.find("alt='render ", p)) != std::string::npos; ++p) ++renders;
  EXPECT_EQ(renders, 8u);
  EXPECT_NE(page.find("<h2>Tables</h2>"), std::string::npos);
  EXPECT_EQ(page.find("src='http"), std::string::npos) << "the page must be self-contained";
  std::size_t imgs = 0;
  for (std::size_t p = 0; (p = page.find("<img ", p)) != std::string::npos; ++p) ++imgs;
  EXPECT_EQ(imgs, renders + 3);

  const std::string chromium = Chromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium not installed (scripts/install_deps.sh installs it)";
  const fs::path profile = dir / "chromium-profile";
  fs::remove_all(profile);
  const CmdResult dom = RunCmd("timeout 120 '" + chromium + "' --headless --no-sandbox --disable-gpu "
                               "--disable-background-networking --disable-component-update --disable-sync "
                               "--no-first-run --disable-dev-shm-usage --user-data-dir='" + profile.string() +
                               "' --virtual-time-budget=20000 --dump-dom 'file://" +
                               fs::absolute(qs / "report.html").string() + "'");
  ASSERT_EQ(dom.code, 0) << dom.output.substr(0, 2000);
  std::smatch m;
  const std::regex check("id=\"image-check\"[^>]*data-ok=\"([0-9]+)\" data-total=\"([0-9]+)\"");
  ASSERT_TRUE(std::regex_search(dom.output, m, check)) << "the page's check script did not run:\n"
                                                      << dom.output.substr(0, 2000);
  EXPECT_EQ(std::stoul(m[2]), imgs);
  EXPECT_EQ(m[1], m[2]) << "some images did not load";
  EXPECT_EQ(dom.output.find("data-loaded=\"0\""), std::string::npos);
}


TEST_F(ReportTest, RenderDrawsMeshesSideBySide) {
  const fs::path dir = TempDir("report_render");
  const fs::path sphere = dir / "sphere.ply", png = dir / "render.png";
  ASSERT_EQ(RunCmd(Arcs() + " shape sphere '" + sphere.string() + "'").code, 0);
  const CmdResult r = RunCmd(Arcs() + " render '" + sphere.string() + "' '" + sphere.string() +
                             "' --labels a,b --out '" + png.string() + "'");
  ASSERT_EQ(r.code, 0) << r.output;
  ASSERT_TRUE(StartsWith(png, "\x89PNG"));
  // PNG IHDR: width at bytes 16-19, big endian; two 300 px panels.
  const std::string s = ReadFile(png);
  const unsigned w = (unsigned char)s[16] << 24 | (unsigned char)s[17] << 16 | (unsigned char)s[18] << 8 |
                     (unsigned char)s[19];
  EXPECT_EQ(w, 600u);
  const CmdResult bad = RunCmd(Arcs() + " render '" + (dir / "none.ply").string() + "' --out '" + png.string() + "'");
  EXPECT_NE(bad.code, 0);
  EXPECT_NE(bad.output.find("none.ply"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace arcs::testing
