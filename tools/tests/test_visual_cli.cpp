// The pictures and animations through the command line: flexmb show, --svg of modes / static /
// sweep, simulate --vtk --html; the HTML page loaded in a real headless browser (Debian chromium):
// it must set document.title to "ok" (no JavaScript error) and its screenshot must show the
// mechanism (pixels in the element colours).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {
const std::string kFlexmb = std::string(FLEXMB_BINARY_DIR) + "/flexmb";
const std::string kData = std::string(FLEXMB_SOURCE_DIR) + "/datfiles/";

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("flexmb_visual_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

// Exit status and combined output of a shell command.
std::pair<int, std::string> run(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return {-1, "popen failed"};
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int st = ::pclose(p);
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out};
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

size_t count(const std::string& hay, const std::string& needle) {
  size_t n = 0;
  for (size_t at = 0; (at = hay.find(needle, at)) != std::string::npos; at += needle.size()) ++n;
  return n;
}

std::string chromium() {
  for (const char* c : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (fs::exists(c)) return c;
  return "";
}

// Headless chromium with a fresh profile and no network services.
std::string browser(const std::string& exe, const fs::path& profile, const std::string& extra) {
  return exe +
         " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking "
         "--disable-component-update --disable-sync --user-data-dir=" +
         profile.string() + " " + extra;
}

// An 8-bit RGB(A) PNG's rows (Python): load(path) -> (width, height, bytes per pixel, rows).
const std::string kPngDecoder = R"PY(
import sys, zlib, struct
def load(path):
    data = open(path, 'rb').read()
    assert data[:8] == b'\x89PNG\r\n\x1a\n'
    pos, idat = 8, b''
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b'IHDR':
            w, h, depth, ctype = struct.unpack('>IIBB', body[:10])
        elif kind == b'IDAT':
            idat += body
        pos += 12 + n
    assert depth == 8 and ctype in (2, 6)
    bpp = 3 if ctype == 2 else 4
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev, i = [], bytearray(stride), 0
    for y in range(h):
        f = raw[i]; line = bytearray(raw[i + 1:i + 1 + stride]); i += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]; c = prev[x - bpp] if x >= bpp else 0
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + b) & 255
            elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line); prev = line
    return w, h, bpp, rows
)PY";

// Counts pixels near the given colours: "width height n1 n2 ...".
const std::string kPngPixels = kPngDecoder + R"PY(
w, h, bpp, rows = load(sys.argv[1])
stride = w * bpp
targets = [tuple(int(t[k:k + 2], 16) for k in (0, 2, 4)) for t in sys.argv[2:]]
counts = [0] * len(targets)
for line in rows:
    for x in range(0, stride, bpp):
        px = line[x:x + 3]
        for k, t in enumerate(targets):
            if abs(px[0] - t[0]) + abs(px[1] - t[1]) + abs(px[2] - t[2]) < 40: counts[k] += 1
print(w, h, *counts)
)PY";
}  // namespace

TEST(VisualCli, ShowDrawsTheModelWithNumbersAndRoles) {
  TempDir dir;
  const fs::path svg = dir.path / "m.svg";
  const auto [rc, out] = run(kFlexmb + " show " + kData + "manipulator.dat --out " + svg.string());
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("wrote " + svg.string()), std::string::npos);
  // Its manifest beside it, as every command that writes files has (issue 35).
  const std::string manifest = slurp(dir.path / "m_run.txt");
  EXPECT_NE(manifest.find("command: show"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("file: m.svg"), std::string::npos) << manifest;
  const std::string s = slurp(svg);
  for (int e : {1, 2, 11, 14, 21, 24}) EXPECT_NE(s.find(">[" + std::to_string(e) + "]<"), std::string::npos) << e;
  EXPECT_NE(s.find("18 degrees of freedom"), std::string::npos);
  EXPECT_NE(s.find("kinematic check: well posed"), std::string::npos);
  EXPECT_NE(s.find("1 (0, 0): fixed"), std::string::npos);
  EXPECT_EQ(count(s, "class=\"element\""), 8u);  // the eight beams; the two hinges are joints
  EXPECT_EQ(count(s, "class=\"joint\""), 2u);

  // An ill-posed model is still drawn, with the problem in the notes; bad options and files fail.
  const auto [rc2, out2] =
      run(kFlexmb + " show " + kData + "tests/underconstrained.dat --out " + (dir.path / "u.svg").string());
  EXPECT_EQ(rc2, 0) << out2;
  EXPECT_NE(slurp(dir.path / "u.svg").find("UNDER-DETERMINED"), std::string::npos);
  EXPECT_EQ(run(kFlexmb + " show " + kData + "manipulator.dat --view top --out " + (dir.path / "v.svg").string()).first,
            2);
  EXPECT_EQ(run(kFlexmb + " show " + (dir.path / "missing.dat").string()).first, 1);  // input error
  EXPECT_EQ(
      run(kFlexmb + " show " + kData + "manipulator.dat --out " + (dir.path / "no/such/folder.svg").string()).first, 1);
  EXPECT_EQ(run(kFlexmb + " show --help").first, 0);
  // --out without an extension: the picture gets `.svg` (issue 35).
  const auto [rc3, out3] = run(kFlexmb + " show " + kData + "manipulator.dat --out " + (dir.path / "bare").string());
  EXPECT_EQ(rc3, 0) << out3;
  EXPECT_TRUE(fs::exists(dir.path / "bare.svg")) << out3;
  EXPECT_FALSE(fs::exists(dir.path / "bare"));
}

TEST(VisualCli, ModesStaticAndSweepDrawTheirShapes) {
  TempDir dir;
  const fs::path modes = dir.path / "modes.svg", stat = dir.path / "static.svg", sweep = dir.path / "sweep.svg";
  auto r = run(kFlexmb + " modes " + kData + "manipulator.dat --nev 3 --svg " + modes.string());
  ASSERT_EQ(r.first, 0) << r.second;
  // One panel for the configuration and one per mode, titled with the frequency printed above.
  std::string s = slurp(modes);
  EXPECT_EQ(count(s, "class=\"panel\""), 4u);
  EXPECT_NE(s.find("mode 3, "), std::string::npos);

  r = run("cd " + dir.path.string() + " && " + kFlexmb + " static " + kData + "straight_guidance.dat --nev 2 --svg " +
          stat.string());
  ASSERT_EQ(r.first, 0) << r.second;
  s = slurp(stat);
  EXPECT_EQ(count(s, "class=\"panel\""), 3u);
  EXPECT_NE(s.find("load factor 1"), std::string::npos);

  r = run("cd " + dir.path.string() + " && " + kFlexmb + " sweep " + kData +
          "straight_guidance.dat --node 6 --comp 1 --from -0.05 --to 0.05 --steps 3 --nev 2 --svg " + sweep.string());
  ASSERT_EQ(r.first, 0) << r.second;
  s = slurp(sweep);
  EXPECT_EQ(count(s, "class=\"panel\""), 1u + 2u + 2u);  // configurations, 2 modes at each end
  EXPECT_NE(s.find("value 0.05: mode 2"), std::string::npos);
  EXPECT_NE(s.find("value -0.05: mode 1"), std::string::npos);
}

TEST(VisualCli, SimulateWritesParaViewSeriesAndAnAnimationThatPlaysInABrowser) {
  TempDir dir;
  const fs::path prefix = dir.path / "sc";
  const auto [rc, out] = run(kFlexmb + " simulate " + kData +
                             "slider_crank_s95.dat --format none --vtk --html -q --out " + prefix.string());
  ASSERT_EQ(rc, 0) << out;
  const std::string pvd = slurp(dir.path / "sc.pvd");
  const size_t sets = count(pvd, "<DataSet ");
  EXPECT_EQ(sets, 501u);  // TIMESTEP: 500 intervals
  size_t vtus = 0;
  for (const auto& f : fs::directory_iterator(dir.path / "sc_vtu")) vtus += f.path().extension() == ".vtu";
  EXPECT_EQ(vtus, sets);
  const fs::path html = dir.path / "sc.html";
  ASSERT_TRUE(fs::exists(html));

  const std::string exe = chromium();
  if (exe.empty()) GTEST_SKIP() << "chromium is not installed (tools/setup.sh installs it): the page was not loaded";
  const fs::path profile = dir.path / "profile";
  fs::create_directories(profile);
  const auto dom = run("timeout 120 " + browser(exe, profile, "--dump-dom file://" + html.string()) + " 2>/dev/null");
  EXPECT_NE(dom.second.find("<title>ok</title>"), std::string::npos) << dom.second.substr(0, 400);

  const fs::path png = dir.path / "shot.png", script = dir.path / "png.py";
  fs::remove_all(profile);
  fs::create_directories(profile);
  run("timeout 120 " +
      browser(exe, profile,
              "--hide-scrollbars --window-size=1000,720 --screenshot=" + png.string() + " file://" + html.string()));
  ASSERT_TRUE(fs::exists(png)) << "no screenshot";
  std::ofstream(script) << kPngPixels;
  // Element colours: rigid crank #444444, flexible (DOF) rod #0072B2.
  const auto px = run("/usr/bin/python3 " + script.string() + " " + png.string() + " 444444 0072B2");
  ASSERT_EQ(px.first, 0) << px.second;
  std::istringstream in(px.second);
  int w = 0, h = 0, grey = 0, blue = 0;
  in >> w >> h >> grey >> blue;
  EXPECT_EQ(w, 1000);
  EXPECT_EQ(h, 720);
  // The crank (about 190 px long, 3.5 px wide) and the rod (about 450 px) are drawn.
  EXPECT_GT(grey, 300) << px.second;
  EXPECT_GT(blue, 800) << px.second;
}

namespace {
// Pixels of a screenshot inside the canvas (960 x 600 at (13, 38)): "width height mechanism
// changed", mechanism = not white and not the light grey of traces and borders; with a second
// screenshot, changed = canvas pixels that are mechanism in exactly one of the two.
const std::string kCanvasPixels = kPngDecoder + R"PY(
def canvas(path):
    w, h, bpp, rows = load(path)
    mask = set()
    for y in range(40, 40 + 590):
        line = rows[y]
        for x in range(15, 15 + 950):
            r, g, b = line[bpp * x], line[bpp * x + 1], line[bpp * x + 2]
            if r + g + b < 600 and max(r, g, b) - min(r, g, b) + (255 - max(r, g, b)) > 40:
                mask.add((x, y))
    return w, h, mask
w, h, m1 = canvas(sys.argv[1])
changed = len(m1 ^ canvas(sys.argv[2])[2]) if len(sys.argv) > 2 else 0
print(w, h, len(m1), changed)
)PY";

// Mechanism pixels (as kCanvasPixels) on the canvas' outermost 4 px: "width height mechanism border".
const std::string kCanvasBorder = kCanvasPixels.substr(0, kCanvasPixels.find("w, h, m1 = canvas")) + R"PY(
w, h, m = canvas(sys.argv[1])
border = sum(1 for (x, y) in m if x < 19 or x >= 15 + 950 - 4 or y < 44 or y >= 40 + 590 - 4)
print(w, h, len(m), border)
)PY";
}  // namespace

namespace {
// Per panel of a shape figure (its frame read from the SVG; the axes' corner left out): "shape
// reference visible", the pixels in the shape's colour (#D55E00 and its shades), in the reference's
// grey, and the reference's pixels more than 3 px from any shape pixel (the rest configuration seen
// beside the moved one, not covered by it or coinciding with it).
const std::string kPanelPixels = kPngDecoder + R"PY(
import re
w, h, bpp, rows = load(sys.argv[1])
svg = open(sys.argv[2]).read()
rects = re.findall(r'<rect x="([0-9.]+)" y="([0-9.]+)" width="([0-9.]+)" height="([0-9.]+)" fill="none" stroke="#dddddd"', svg)
for x0, y0, pw, ph in ((int(float(a)), int(float(b)), int(float(c)), int(float(d))) for a, b, c, d in rects):
    shape, grey = set(), set()
    for y in range(y0 + 24, min(h, y0 + ph - 2)):
        for x in range(x0 + 2, min(w, x0 + pw - 2)):
            if x > x0 + pw - 80 and y > y0 + ph - 80: continue
            r, g, b = rows[y][bpp * x:bpp * x + 3]
            if r > 150 and g < 150 and b < 100: shape.add((x, y))
            elif abs(r - g) < 12 and abs(g - b) < 12 and 90 < r < 210: grey.add((x, y))
    visible = sum(1 for (x, y) in grey if not any((x + i, y + j) in shape for i in range(-3, 4) for j in range(-3, 4)))
    print(len(shape), len(grey), visible)
)PY";
}  // namespace

// kPanelPixels of a shape figure's screenshot (headless chromium): per panel its shape, reference
// and visible reference pixels; empty when the browser is missing or the screenshot failed.
struct PanelPixels {
  int shape = 0, grey = 0, visible = 0;
};
std::vector<PanelPixels> panelPixels(const fs::path& dir, const fs::path& svg) {
  const std::string exe = chromium();
  if (exe.empty()) return {};
  const fs::path png = dir / (svg.stem().string() + ".png"), profile = dir / "profile", script = dir / "panels.py";
  const std::string head = slurp(svg).substr(0, 300);
  const auto number = [&](const std::string& key) {
    const size_t at = head.find(key + "=\"");
    return at == std::string::npos ? 0 : std::atoi(head.c_str() + at + key.size() + 2);
  };
  fs::create_directories(profile);
  run("timeout 120 " +
      browser(exe, profile,
              "--hide-scrollbars --window-size=" + std::to_string(number("width")) + "," +
                  std::to_string(number("height")) + " --screenshot=" + png.string() + " file://" + svg.string()));
  std::ofstream(script) << kPanelPixels;
  std::istringstream in(run("/usr/bin/python3 " + script.string() + " " + png.string() + " " + svg.string()).second);
  std::vector<PanelPixels> panels;
  for (PanelPixels p; in >> p.shape >> p.grey >> p.visible;) panels.push_back(p);
  return panels;
}

TEST(VisualCli, ThePivotsRotationModeIsSeenToRotate) {
  // Issue 35: in the iso view the pivot's mode 1 (its working rotation) looked like its rest shape:
  // the solid leaves covered it (measured with --view iso: 0 of 156 reference pixels visible). By
  // default the panel is drawn in the plane it moves in and the rest shape is seen beside the moved
  // one (measured: 330 of 649).
  TempDir dir;
  const auto [rc, out] = run("cd " + dir.path.string() + " && " + kFlexmb + " modes " + kData +
                             "spatial/cross_spring_pivot.dat --nev 2 --svg m.svg -q");
  ASSERT_EQ(rc, 0) << out;
  if (chromium().empty())
    GTEST_SKIP() << "chromium is not installed (tools/setup.sh installs it): the figure was not drawn";
  const std::vector<PanelPixels> px = panelPixels(dir.path, dir.path / "m.svg");
  ASSERT_GE(px.size(), 2u) << "no screenshot";
  EXPECT_EQ(px[0].shape, 0);  // the first panel is the rest configuration alone
  EXPECT_GT(px[0].grey, 300);
  EXPECT_GT(px[1].shape, 300);               // mode 1 is drawn ...
  EXPECT_GT(px[1].visible, px[1].grey / 4);  // ... and the rest shape is seen beside it
}

TEST(VisualCli, TheLeafSpringStagesModesShowItsLeaves) {
  // Issue 51: a parallel leaf-spring stage standing in xz moves along x alone (mode 1), which xy
  // contains too; auto drew every panel from the top, where the stage block hid the leaves. Now
  // each panel is in xz, the note says so, and the leaves' rest lines are seen beside the bent ones.
  TempDir dir;
  const std::string stage = kData + "spatial/parallel_leaf_stage.dat";
  auto r = run("cd " + dir.path.string() + " && " + kFlexmb + " modes " + stage + " --nev 2 --svg m.svg -q && " +
               kFlexmb + " modes " + stage + " --nev 2 --svg top.svg --view xy -q && " + kFlexmb + " static " + stage +
               " --nev 1 --format none --svg s.svg -q");
  ASSERT_EQ(r.first, 0) << r.second;
  EXPECT_NE(slurp(dir.path / "m.svg").find("views, panel by panel: xz, xz, xz (auto: the one that sees most"),
            std::string::npos);
  // static: the load steps (along x) and the last step's mode.
  EXPECT_NE(slurp(dir.path / "s.svg").find("views, panel by panel: xz, xz (auto"), std::string::npos);
  if (chromium().empty())
    GTEST_SKIP() << "chromium is not installed (tools/setup.sh installs it): the figure was not drawn";
  const std::vector<PanelPixels> px = panelPixels(dir.path, dir.path / "m.svg"),
                                 top = panelPixels(dir.path, dir.path / "top.svg");
  ASSERT_GE(px.size(), 2u) << "no screenshot";
  ASSERT_GE(top.size(), 2u) << "no screenshot";
  std::printf("mode 1 of the stage: %d of %d reference pixels seen (from the top: %d of %d)\n", px[1].visible,
              px[1].grey, top[1].visible, top[1].grey);
  EXPECT_GT(px[1].shape, 300);
  EXPECT_GT(px[1].visible, 100);                 // the leaves' rest lines beside the bent leaves ...
  EXPECT_GT(px[1].visible, 4 * top[1].visible);  // ... which the top view hides (measured: 150 and 0)
}

TEST(VisualCli, ShowNamesBeamwRolesAndWarpingNodesAsTheyAre) {
  // Issue 35: the BEAMW pivot's rigid platform was coloured as released (its warping is released,
  // as in every BEAMW), warping nodes were labelled with a planar rotation's theta, the element rows
  // ran past the picture's right edge, and the normalisation elements flexmb adds were counted and
  // listed as the user's.
  TempDir dir;
  const fs::path svg = dir.path / "bw.svg";
  const auto [rc, out] =
      run(kFlexmb + " show " + kData + "spatial/cross_spring_pivot_beamw.dat -q --out " + svg.string());
  ASSERT_EQ(rc, 0) << out;
  const std::string s = slurp(svg);
  EXPECT_NE(s.find(", 7 elements;"), std::string::npos);
  EXPECT_EQ(s.find("L2MIN1"), std::string::npos);
  EXPECT_NE(s.find("and 6 normalisation constraints"), std::string::npos);
  EXPECT_NE(s.find(">  w15 (0): DOF<"), std::string::npos);
  EXPECT_EQ(s.find("\u03b815"), std::string::npos);
  // Element 4, the platform: rigid apart from its warping, drawn and listed in the rigid colour.
  const size_t row = s.find(">  4 BEAMW (4 5 6 7 8 9): elongation rigid");
  ASSERT_NE(row, std::string::npos);
  const size_t tag = s.rfind("<text", row);
  EXPECT_NE(s.substr(tag, row - tag).find("fill=\"#444444\""), std::string::npos) << s.substr(tag, 200);
  // No table row wider than the picture: every row at most 100 characters plus its indent.
  size_t longest = 0;
  for (size_t at = 0; (at = s.find(">  ", at)) != std::string::npos; ++at)
    longest = std::max(longest, s.find("</text>", at) - at);
  EXPECT_LE(longest, 110u);
  const size_t wAt = s.find("width=\"");
  ASSERT_NE(wAt, std::string::npos);
  EXPECT_LT(std::atof(s.c_str() + wAt + 7), 1400.0);
}

TEST(VisualCli, ALargeModelIsDrawnFirstWithNumbersThatDoNotPileUp) {
  // Issue 35: the cross-spring pivot (41 beams) was a 1612 x 2464 page whose first screen was the
  // node table, and the numbers along an edge-on leaf piled up.
  TempDir dir;
  const fs::path svg = dir.path / "p.svg";
  const auto [rc, out] = run(kFlexmb + " show " + kData + "spatial/cross_spring_pivot.dat -q --out " + svg.string());
  ASSERT_EQ(rc, 0) << out;
  const std::string s = slurp(svg);
  // The table below the drawing: its heading lower than the legend, the page no wider than the drawing.
  const size_t heading = s.find(">nodes (coordinates: role)<"), legend = s.find("<g class=\"legend\"");
  ASSERT_NE(heading, std::string::npos);
  ASSERT_NE(legend, std::string::npos);
  auto yOf = [&](size_t at) {
    const size_t y = s.rfind(" y=\"", at);
    return std::atof(s.c_str() + y + 4);
  };
  EXPECT_GT(yOf(heading), yOf(s.find("element: rigid", legend)));
  const size_t wAt = s.find("width=\"");
  EXPECT_LE(std::atof(s.c_str() + wAt + 7), 1000.0);
  EXPECT_NE(s.find("numbers left out where they would overlap"), std::string::npos);
  EXPECT_NE(s.find(", 41 elements;"), std::string::npos);  // the 42 normalisations are not counted
}

TEST(VisualCli, ThePageOpensWithTheWholeModelInView) {
  // The cross-spring pivot's leaves are 50 mm wide against 100 mm long: fitted to the centre lines
  // alone, the page cut the leaves and the platform off (issue 35).
  TempDir dir;
  const auto [rc, out] = run("cd " + dir.path.string() + " && " + kFlexmb + " show " + kData +
                             "spatial/cross_spring_pivot.dat --html p.html -q");
  ASSERT_EQ(rc, 0) << out;
  const std::string exe = chromium();
  if (exe.empty()) GTEST_SKIP() << "chromium is not installed (tools/setup.sh installs it): the page was not loaded";
  const fs::path html = dir.path / "p.html", png = dir.path / "p.png", profile = dir.path / "profile",
                 script = dir.path / "border.py";
  fs::create_directories(profile);
  run("timeout 120 " + browser(exe, profile,
                               "--hide-scrollbars --window-size=1000,720 --screenshot=" + png.string() + " 'file://" +
                                   html.string() + "#pause'"));
  ASSERT_TRUE(fs::exists(png)) << "no screenshot";
  std::ofstream(script) << kCanvasBorder;
  const auto px = run("/usr/bin/python3 " + script.string() + " " + png.string());
  ASSERT_EQ(px.first, 0) << px.second;
  std::istringstream in(px.second);
  int w = 0, h = 0, mech = 0, border = 0;
  in >> w >> h >> mech >> border;
  EXPECT_GT(mech, 20000) << px.second;  // drawn, and large
  EXPECT_EQ(border, 0) << px.second;    // nothing runs off the canvas

  // A mode shape bent out of plane (mode 4 at its largest): the initial configuration's dashed
  // centre lines are drawn over the solid leaves, and are gone with #noreference.
  const auto modes = run("cd " + dir.path.string() + " && " + kFlexmb + " modes " + kData +
                         "spatial/cross_spring_pivot.dat --html m.html --out m -q");
  ASSERT_EQ(modes.first, 0) << modes.second;
  auto dashed = [&](const std::string& fragment, const std::string& name) {
    const fs::path shot = dir.path / (name + ".png"), prof = dir.path / ("profile_" + name);
    fs::create_directories(prof);
    run("timeout 120 " + browser(exe, prof,
                                 "--hide-scrollbars --window-size=1000,720 --screenshot=" + shot.string() +
                                     " 'file://" + (dir.path / "m.html").string() + fragment + "'"));
    const fs::path count = dir.path / "count.py";
    std::ofstream(count) << kPngPixels;
    const auto r = run("/usr/bin/python3 " + count.string() + " " + shot.string() + " 888888");
    std::istringstream is(r.second);
    int sw = 0, sh = 0, grey = 0;
    is >> sw >> sh >> grey;
    return grey;
  };
  const int with = dashed("#pause&seq=3&frame=6", "with"),
            without = dashed("#pause&seq=3&frame=6&noreference", "without");
  EXPECT_GT(with, without + 150) << with << " against " << without;
}

TEST(VisualCli, SpatialModelsAreDrawnInThreeDimensions) {
  TempDir dir;
  const std::string pivot = kData + "spatial/cross_spring_pivot_coarse.dat";
  // show: iso by default, every element drawn with its cross-section (faces), the position nodes as
  // markers (orientation nodes only as labels), the table with position and Euler-parameter nodes.
  for (const char* view : {"", "iso", "xy", "xz", "yz"}) {
    const fs::path svg = dir.path / (std::string("pivot_") + view + ".svg");
    const auto [rc, out] =
        run(kFlexmb + " show " + pivot + (*view ? std::string(" --view ") + view : "") + " --out " + svg.string());
    ASSERT_EQ(rc, 0) << out;
    const std::string s = slurp(svg);
    for (int e = 1; e <= 7; ++e) {
      EXPECT_NE(s.find("class=\"face\" data-element=\"" + std::to_string(e) + "\""), std::string::npos) << view << e;
      EXPECT_NE(s.find(">[" + std::to_string(e) + "]<"), std::string::npos) << view << e;
    }
    // The 8 position nodes, no orientation node (the legend's five node markers come after).
    EXPECT_EQ(count(s.substr(0, s.find("<g class=\"legend\"")), "class=\"node "), 8u) << view;
    EXPECT_NE(s.find("  1 (0, 0, 0): fixed"), std::string::npos);
    EXPECT_NE(s.find("  \u03bb2 (1, 0, 0, 0): fixed"), std::string::npos);
    EXPECT_EQ(s.find("\u03b83 "), std::string::npos);  // no position node labelled as an orientation node
    EXPECT_NE(s.find("class=\"axes\""), std::string::npos);
  }
  // The same picture from different sides differs.
  EXPECT_NE(slurp(dir.path / "pivot_xy.svg"), slurp(dir.path / "pivot_iso.svg"));
  EXPECT_EQ(slurp(dir.path / "pivot_.svg"), slurp(dir.path / "pivot_iso.svg"));

  // modes --svg / --html / --vtk and static --svg / --html / --vtk.
  auto r = run("cd " + dir.path.string() + " && " + kFlexmb + " modes " + pivot +
               " --nev 3 --svg m.svg --html m.html --vtk m");
  ASSERT_EQ(r.first, 0) << r.second;
  std::string s = slurp(dir.path / "m.svg");
  EXPECT_EQ(count(s, "class=\"panel\""), 4u);
  EXPECT_GT(count(s, "class=\"face\""), 100u);
  EXPECT_GE(count(slurp(dir.path / "m.pvd"), "<DataSet "), 3u);
  // Auto: each panel in the view that sees most of it (the note names them); --view sets one for all.
  EXPECT_NE(s.find("views, panel by panel: "), std::string::npos);
  r = run("cd " + dir.path.string() + " && " + kFlexmb + " modes " + pivot + " --nev 3 --svg mxz.svg --view xz -q");
  ASSERT_EQ(r.first, 0) << r.second;
  const std::string xz = slurp(dir.path / "mxz.svg");
  EXPECT_NE(xz, s);
  EXPECT_EQ(xz.find("views, panel by panel: "), std::string::npos);
  for (const std::string command : {" modes ", " static ", " sweep --node 2 --from 0 --to 0.01 "}) {
    const auto bad = run(kFlexmb + command + pivot + " --svg b.svg --view top");
    EXPECT_EQ(bad.first, 2) << command << bad.second;
    EXPECT_NE(bad.second.find("--view must be auto, xy, xz, yz or iso, not 'top'"), std::string::npos) << bad.second;
  }
  s = slurp(dir.path / "m.html");
  EXPECT_NE(s.find("\"name\":\"mode 3, "), std::string::npos);
  r = run("cd " + dir.path.string() + " && " + kFlexmb + " static " + pivot + " --nev 2 --svg s.svg --html --vtk -q");
  ASSERT_EQ(r.first, 0) << r.second;
  EXPECT_EQ(count(slurp(dir.path / "s.svg"), "class=\"panel\""), 3u);
  // Its load steps deflect it by a few per cent: drawn magnified, the factor in the panel's title.
  EXPECT_NE(slurp(dir.path / "s.svg").find("configurations (displacements x "), std::string::npos);
  // ITERSTEP's 9 steps: SPACAR's load steps 0..9.
  EXPECT_EQ(count(slurp(dir.path / "cross_spring_pivot_coarse_static.pvd"), "<DataSet "), 10u);
  s = slurp(dir.path / "cross_spring_pivot_coarse_static.html");
  EXPECT_NE(s.find("\"name\":\"load steps\""), std::string::npos);
  EXPECT_NE(s.find("load factor 1: mode 2"), std::string::npos);
}

TEST(VisualCli, SpatialMotionInParaViewAndInABrowserThatRotatesTheView) {
  TempDir dir;
  const fs::path prefix = dir.path / "wg";
  const auto [rc, out] = run(kFlexmb + " simulate " + kData +
                             "spatial/wire_guidance.dat --format none --vtk --html -q --out " + prefix.string());
  ASSERT_EQ(rc, 0) << out;
  // Every .vtu has the 8 beams: 8 x 9 points, 8 cells, with displacement, rotation and stress.
  const std::string vtu = slurp(dir.path / "wg_vtu" / "wg_00010.vtu");
  EXPECT_NE(vtu.find("NumberOfPoints=\"72\" NumberOfCells=\"8\""), std::string::npos) << vtu.substr(0, 600);
  for (const char* field : {"Name=\"displacement\"", "Name=\"rotation\"", "Name=\"stress\"", "Name=\"deformation\""})
    EXPECT_NE(vtu.find(field), std::string::npos) << field;
  EXPECT_EQ(count(slurp(dir.path / "wg.pvd"), "<DataSet "), 31u);

  const std::string exe = chromium();
  if (exe.empty()) GTEST_SKIP() << "chromium is not installed (tools/setup.sh installs it): the page was not loaded";
  const fs::path html = dir.path / "wg.html";
  ASSERT_TRUE(fs::exists(html));
  auto shot = [&](const std::string& fragment, const fs::path& png) {
    const fs::path profile = dir.path / ("profile_" + png.stem().string());
    fs::create_directories(profile);
    const auto dom =
        run("timeout 120 " + browser(exe, profile, "--dump-dom 'file://" + html.string() + fragment + "'") +
            " 2>/dev/null");
    fs::remove_all(profile);
    fs::create_directories(profile);
    run("timeout 120 " + browser(exe, profile,
                                 "--hide-scrollbars --window-size=1000,720 --screenshot=" + png.string() + " 'file://" +
                                     html.string() + fragment + "'"));
    const size_t at = dom.second.find("<title>");
    return at == std::string::npos ? std::string() : dom.second.substr(at + 7, dom.second.find("</title>") - at - 7);
  };
  const fs::path iso = dir.path / "iso.png", turned = dir.path / "turned.png";
  EXPECT_EQ(shot("#pause", iso), "ok");
  const std::string title = shot("#pause&drag=180,-60", turned);
  // The page opens in MATLAB's view(3) (azimuth -37.5 degrees, the page's -127.5: measured from +x,
  // elevation 30). A drag of 180 px to the right turns the azimuth by -90 degrees (-127.5 -> -217.5),
  // 60 px up the elevation by -30 (30 -> 0).
  EXPECT_EQ(title, "ok az=-217.5 el=0.0");
  ASSERT_TRUE(fs::exists(iso));
  ASSERT_TRUE(fs::exists(turned));
  const fs::path script = dir.path / "canvas.py";
  std::ofstream(script) << kCanvasPixels;
  const auto px = run("/usr/bin/python3 " + script.string() + " " + iso.string() + " " + turned.string());
  ASSERT_EQ(px.first, 0) << px.second;
  std::istringstream in(px.second);
  int w = 0, h = 0, mech = 0, changed = 0;
  in >> w >> h >> mech >> changed;
  EXPECT_EQ(w, 1000);
  EXPECT_EQ(h, 720);
  // The guidance (four wires and a platform frame, drawn as solids) covers a good part of the canvas,
  // and the rotated view shows it from another side.
  EXPECT_GT(mech, 20000) << px.second;
  EXPECT_GT(changed, mech / 4) << px.second;
}
