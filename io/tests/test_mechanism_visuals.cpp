// MechanismGeometry, MechanismSvg, VtkWriter and HtmlAnimation: point layout, the beam's shape
// against its displacement field, and the documents' structure (parsed by Python's XML parser).
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/formats/DatReader.hpp"
#include "io/pictures/HtmlAnimation.hpp"
#include "io/pictures/MechanismGeometry.hpp"
#include "io/pictures/MechanismSvg.hpp"
#include "io/pictures/VtkWriter.hpp"

using namespace flexmb;
namespace fs = std::filesystem;

namespace {
core::Model twoLink() { return io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/io/tests/data/two_link_2013.dat"); }

// A clamped horizontal beam of length 2 (nodes 1 fixed, 2 free).
core::Model cantilever() {
  return io::readDatString(
      "PLBEAM 1 1 2 3 4\nX 1 0 0\nX 3 2 0\nFIX 1\nFIX 2\nDYNE 1 1 2 3\nEND\nHALT\nESTIFF 1 1e6 1e3\nEM 1 1\nEND\nEND\n",
      "cantilever.dat");
}

// `frames` states at times 0, dt, 2 dt, ...: the initial configuration with node `label` raised by
// 0.01 m per frame; with `rates`, zero velocities and accelerations and deformations, their rates
// and stresses all 0.5 per frame.
core::Trajectory risingNode(const core::Model& m, int label, int frames, double dt, bool rates) {
  core::Trajectory traj;
  for (int k = 0; k < frames; ++k) {
    core::StateOutputs s;
    s.x = m.x0;
    s.x[m.nodes[m.nodeByLabel.at(label)].firstCoord + 1] += 0.01 * k;
    if (rates) {
      s.xd = s.xdd = Eigen::VectorXd::Zero(m.nx);
      s.e = s.ed = s.edd = s.sig = Eigen::VectorXd::Constant(m.ne, 0.5 * k);
    }
    traj.time.push_back(dt * k);
    traj.states.push_back(s);
  }
  return traj;
}

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("flexmb_visuals_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

std::string run(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return "popen failed";
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int rc = ::pclose(p);
  return rc == 0 ? out : "FAILED(" + std::to_string(rc) + "): " + out;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Parses a .vtu and prints: points cells, then "name components tuples" per DataArray.
const char* kVtuSummary = R"PY(
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
piece = root.find('UnstructuredGrid/Piece')
print(piece.get('NumberOfPoints'), piece.get('NumberOfCells'))
for sec in ['Points', 'Cells', 'PointData', 'CellData']:
    for a in piece.find(sec).findall('DataArray'):
        vals = a.text.split()
        c = int(a.get('NumberOfComponents', '1'))
        assert len(vals) % c == 0, a.get('Name')
        [float(v) for v in vals]
        print(sec, a.get('Name'), c, len(vals) // c)
)PY";
}  // namespace

TEST(MechanismGeometry, PointLayoutOfBeamsHingeAndTruss) {
  const core::Model m = twoLink();
  const io::MechanismGeometry g(m, 8);
  // Two beams of 9 points, the hinge at one point, the truss through its 2 nodes.
  ASSERT_EQ(g.elements().size(), 4u);
  EXPECT_EQ(g.numPoints(), 9 + 9 + 1 + 2);
  EXPECT_EQ(g.elements()[2].shape, io::DrawnShape::Joint);
  std::vector<io::Point3> p;
  g.points(m.x0, p);
  ASSERT_EQ(static_cast<int>(p.size()), g.numPoints());
  // Beam 1 from (0,0) to (0.5,0): ends at its nodes, interior on the chord (no deformation).
  EXPECT_DOUBLE_EQ(p[0].x, 0.0);
  EXPECT_DOUBLE_EQ(p[8].x, 0.5);
  for (int k = 0; k <= 8; ++k) EXPECT_NEAR(p[k].y, 0.0, 1e-15);
  EXPECT_NEAR(p[4].x, 0.25, 1e-15);
  // The hinge (ground orientation 7 to the beam's orientation 2) sits at beam 1's node 1.
  EXPECT_DOUBLE_EQ(p[18].x, 0.0);
  EXPECT_DOUBLE_EQ(p[18].y, 0.0);
  // Truss 4 from node 5 (1,0) to node 8 (1,1).
  EXPECT_DOUBLE_EQ(p[19].x, 1.0);
  EXPECT_DOUBLE_EQ(p[20].y, 1.0);
  EXPECT_EQ(m.nodes[g.pointNodes()[19]].label, 5);
  EXPECT_EQ(g.pointNodes()[4], -1);
  EXPECT_FALSE(g.spatial());
}

TEST(MechanismGeometry, BeamCurveFollowsTheBeamDisplacementField) {
  const core::Model m = cantilever();
  const io::MechanismGeometry g(m, 4);
  // Rotate the free end's orientation node by theta: e3 = -l0 sin(theta), e2 = 0, so the middle of
  // the beam lies at w(1/2) = H3(1/2) e3 = -l0 sin(theta) / 8 from the chord.
  const double theta = 0.1, l0 = 2.0;
  Eigen::VectorXd x = m.x0;
  const int phiq = m.nodes[m.nodeByLabel.at(4)].firstCoord;
  x[phiq] += theta;
  std::vector<io::Point3> p;
  g.points(x, p);
  ASSERT_EQ(p.size(), 5u);
  EXPECT_NEAR(p[2].x, 1.0, 1e-14);
  EXPECT_NEAR(p[2].y, -l0 * std::sin(theta) / 8, 1e-14);
  // Quarter point: H3(1/4) = 1/16 * 3/4.
  EXPECT_NEAR(p[1].y, -l0 * std::sin(theta) * 3.0 / 64.0, 1e-14);
}

TEST(MechanismGeometry, ScaledShapeUsesTheRequestedFraction) {
  const core::Model m = cantilever();
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(m.nx);
  const int yq = m.nodes[m.nodeByLabel.at(3)].firstCoord + 1;
  dx[yq] = 1e-6;
  const Eigen::VectorXd s = io::scaledShape(m, m.x0, dx, 0.1);
  // Model size: half the diagonal of the bounding box (2 x 0) = 1.
  EXPECT_NEAR(s[yq] - m.x0[yq], 0.1, 1e-12);
  // A pure rotation is limited to 0.3 rad.
  dx.setZero();
  dx[m.nodes[m.nodeByLabel.at(4)].firstCoord] = 5.0;
  const Eigen::VectorXd r = io::scaledShape(m, m.x0, dx);
  EXPECT_NEAR(r[m.nodes[m.nodeByLabel.at(4)].firstCoord] - m.x0[m.nodes[m.nodeByLabel.at(4)].firstCoord], 0.3, 1e-12);
}

TEST(MechanismGeometry, SmallDeflectionsAreMagnifiedByARoundFactor) {
  const core::Model m = cantilever();
  const double size = io::modelSize(m, m.x0);
  const int tipY = m.nodes[m.nodeByLabel.at(3)].firstCoord + 1;
  auto deflected = [&](double d) {
    Eigen::VectorXd x = m.x0;
    x[tipY] += d;
    return x;
  };
  // 1 % of the size: magnified to at most 12 %, by 1, 2 or 5 times a power of ten.
  const double k = io::magnification(m, m.x0, {deflected(0.002 * size), deflected(0.01 * size)});
  EXPECT_EQ(k, 10.0);
  EXPECT_EQ(io::magnification(m, m.x0, {deflected(0.004 * size)}), 20.0);  // 30 -> 20
  // Visible as it is (5 % and more), or no motion at all: drawn at true scale.
  EXPECT_EQ(io::magnification(m, m.x0, {deflected(0.06 * size)}), 1.0);
  EXPECT_EQ(io::magnification(m, m.x0, {m.x0}), 1.0);
}

TEST(MechanismSvg, ModelPictureNamesEveryNodeElementAndRole) {
  const core::Model m = twoLink();
  const io::MechanismGeometry g(m);
  io::ModelDrawing d;
  d.title = "two <link> & \"test\"";
  d.notes = {"note one"};
  const std::string svg = io::renderModelSvg(g, d);
  TempDir dir;
  const fs::path file = dir.path / "model.svg";
  io::writeModelSvg(file.string(), g, d);
  EXPECT_EQ(slurp(file), svg);
  EXPECT_EQ(run("/usr/bin/python3 -c \"import xml.etree.ElementTree as E; E.parse('" + file.string() + "')\" 2>&1"),
            "");
  for (const char* label : {">[1]<", ">[2]<", ">[3]<", ">[4]<"}) EXPECT_NE(svg.find(label), std::string::npos) << label;
  for (const char* node : {">1<", ">3<", ">5<", ">8<"}) EXPECT_NE(svg.find(node), std::string::npos) << node;
  EXPECT_NE(svg.find("two &lt;link&gt; &amp; &quot;test&quot;"), std::string::npos);
  // Roles: node 1 fixed, node 8 partly fixed (x fixed) with y input; beam 1 DOF, truss 4 released,
  // hinge 3 DOF.
  EXPECT_EQ(io::nodeRole(m, m.nodeByLabel.at(1)), "fixed");
  EXPECT_EQ(io::nodeRole(m, m.nodeByLabel.at(8)), "input");
  EXPECT_EQ(io::nodeRole(m, m.nodeByLabel.at(3)), "free");
  EXPECT_EQ(io::elementRole(m, m.elementByLabel.at(4)), "released");
  EXPECT_EQ(io::elementRole(m, m.elementByLabel.at(3)), "DOF");
  EXPECT_NE(svg.find("8 (1, 1): x fixed, y input"), std::string::npos);
  EXPECT_NE(svg.find("4 PLTRUSS (5 8): elongation released"), std::string::npos);
  EXPECT_NE(svg.find("1 PLBEAM (1 2 3 4): elongation rigid, bending p DOF, bending q DOF"), std::string::npos);
  EXPECT_NE(svg.find("class=\"node fixed\""), std::string::npos);
}

TEST(MechanismSvg, ShapeFigureHasOnePanelPerEntryAndOneScale) {
  const core::Model m = cantilever();
  const io::MechanismGeometry g(m);
  io::ShapeFigure f;
  f.title = "shapes";
  Eigen::VectorXd bent = m.x0;
  bent[m.nodes[m.nodeByLabel.at(3)].firstCoord + 1] = 0.2;
  f.panels.push_back({"a", {{m.x0, "initial", "", true}, {bent, "bent", "", false}}});
  f.panels.push_back({"b", {{m.x0, "", "", true}}});
  f.panels.push_back({"wrong size is skipped", {{Eigen::VectorXd::Zero(3), "", "", false}}});
  const std::string svg = io::renderShapesSvg(g, f);
  size_t panels = 0, lines = 0;
  for (size_t at = 0; (at = svg.find("class=\"panel\"", at)) != std::string::npos; ++at) ++panels;
  for (size_t at = 0; (at = svg.find("class=\"element\"", at)) != std::string::npos; ++at) ++lines;
  EXPECT_EQ(panels, 3u);
  EXPECT_EQ(lines, 3u);  // one beam per drawn layer
  EXPECT_NE(svg.find("stroke-dasharray"), std::string::npos);
}

// Every spatial position node of a model moved by f(x, y, z) -> displacement.
template <class Move>
Eigen::VectorXd movedNodes(const core::Model& m, Move move) {
  Eigen::VectorXd x = m.x0;
  for (const core::Node& n : m.nodes) {
    if (n.kind != core::NodeKind::SpatialPosition) continue;
    const Eigen::Vector3d p = m.x0.segment<3>(n.firstCoord);
    x.segment<3>(n.firstCoord) += move(p);
  }
  return x;
}

// Auto (issue 35, issue 51): each panel in the view that sees most of its model and of its motion.
TEST(MechanismSvg, EachPanelIsDrawnInTheViewThatSeesItsModelAndMotion) {
  const core::Model m = io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/cross_spring_pivot.dat");
  const io::MechanismGeometry g(m);
  ASSERT_TRUE(g.spatial());
  auto panel = [&](const Eigen::VectorXd& x) { return io::ShapePanel{"", {{m.x0, "", "", true}, {x, "", "", false}}}; };
  auto view = [&](const Eigen::VectorXd& x) { return io::panelView(g, panel(x), io::View::Auto); };
  // The pivot lies in z = 0, its platform along y. Its working motion, a rotation about z: xy.
  const Eigen::VectorXd turned =
      movedNodes(m, [](const Eigen::Vector3d& p) { return Eigen::Vector3d(-0.05 * p.y(), 0.05 * p.x(), 0.0); });
  EXPECT_EQ(view(turned), io::View::XY);
  // Motion along z: both side views see it; yz sees the leaves at 45 degrees and the platform, xz
  // not the platform. Along y and z: yz alone sees it. In every direction: iso.
  EXPECT_EQ(view(movedNodes(m, [](const Eigen::Vector3d& p) { return Eigen::Vector3d(0, 0, p.x()); })), io::View::YZ);
  EXPECT_EQ(view(movedNodes(m, [](const Eigen::Vector3d& p) { return Eigen::Vector3d(0, p.x(), p.y()); })),
            io::View::YZ);
  const Eigen::VectorXd twisted =
      movedNodes(m, [](const Eigen::Vector3d& p) { return Eigen::Vector3d(p.y(), p.x(), p.x() + p.y()); });
  EXPECT_EQ(view(twisted), io::View::Isometric);
  // A panel without motion: the plane the model lies in. A view the user set is kept.
  EXPECT_EQ(io::panelView(g, io::ShapePanel{"", {{m.x0, "", "", true}}}, io::View::Auto), io::View::XY);
  EXPECT_EQ(io::panelView(g, panel(twisted), io::View::XZ), io::View::XZ);

  // Issue 51: a parallel leaf-spring stage standing in xz (leaves along z). Its guided motion is along
  // x alone, which xy contains too: from the top the stage block hid the leaves. Now xz, the leaves
  // seen bending; out of its plane (along y) yz, where xy would show the stage alone.
  const core::Model st = io::readDatFile(std::string(FLEXMB_SOURCE_DIR) + "/datfiles/spatial/parallel_leaf_stage.dat");
  const io::MechanismGeometry gs(st);
  auto stageView = [&](const Eigen::VectorXd& x) {
    return io::panelView(gs, io::ShapePanel{"", {{st.x0, "", "", true}, {x, "", "", false}}}, io::View::Auto);
  };
  EXPECT_EQ(stageView(movedNodes(st, [](const Eigen::Vector3d& p) { return Eigen::Vector3d(0.1 * p.z(), 0, 0); })),
            io::View::XZ);
  EXPECT_EQ(stageView(movedNodes(st, [](const Eigen::Vector3d& p) { return Eigen::Vector3d(0, 0.1 * p.z(), 0); })),
            io::View::YZ);
  EXPECT_EQ(io::panelView(gs, io::ShapePanel{"", {{st.x0, "", "", true}}}, io::View::Auto), io::View::XZ);
  // In the figure: the rotation's panel carries the xy axes (no z arrow drawn in its plane) and the
  // reference is drawn again over the solid shapes.
  io::ShapeFigure f;
  f.panels.push_back(panel(turned));
  f.panels.push_back(panel(twisted));
  const std::string svg = io::renderShapesSvg(g, f);
  EXPECT_NE(svg.find("class=\"reference-over\""), std::string::npos);
  io::ShapeFigure fixed = f;
  fixed.view = io::View::Isometric;
  EXPECT_NE(io::renderShapesSvg(g, fixed), svg);  // auto drew the first panel in another projection
}

TEST(VtkWriter, SeriesHasOneWellFormedVtuPerOutputTime) {
  const core::Model m = twoLink();
  core::Trajectory traj = risingNode(m, 5, 3, 0.1, true);  // node 5 moves up
  TempDir dir;
  const auto files = io::writeVtkSeries((dir.path / "run").string(), m, traj);
  ASSERT_EQ(files.size(), 4u);
  EXPECT_EQ(fs::path(files[0]).filename(), "run.pvd");
  EXPECT_EQ(fs::path(files[3]).filename(), "run_00002.vtu");
  EXPECT_EQ(fs::path(files[3]).parent_path().filename(), "run_vtu");
  for (const auto& f : files) EXPECT_TRUE(fs::exists(f)) << f;
  const std::string pvd =
      run("/usr/bin/python3 -c \"import xml.etree.ElementTree as E; r = E.parse('" + files[0] +
          "').getroot(); print(' '.join(d.get('timestep') + ':' + d.get('file') for d in r.iter('DataSet')))\"");
  EXPECT_EQ(pvd, "0:run_vtu/run_00000.vtu 0.1:run_vtu/run_00001.vtu 0.2:run_vtu/run_00002.vtu\n");

  const fs::path script = dir.path / "vtu.py";
  std::ofstream(script) << kVtuSummary;
  const std::string summary = run("/usr/bin/python3 " + script.string() + " " + files[3] + " 2>&1");
  std::istringstream in(summary);
  int np = 0, nc = 0;
  in >> np >> nc;
  EXPECT_EQ(np, 21) << summary;
  EXPECT_EQ(nc, 4) << summary;
  for (const char* line : {"Points Points 3 21", "Cells connectivity 1 21", "Cells offsets 1 4", "Cells types 1 4",
                           "PointData displacement 3 21", "PointData node_label 1 21", "CellData element_label 1 4",
                           "CellData deformation 3 4", "CellData deformation_rate 3 4", "CellData stress 3 4"})
    EXPECT_NE(summary.find(line), std::string::npos) << line << "\n" << summary;
  const std::string vtu = slurp(files[3]);
  EXPECT_NE(vtu.find("0.2</DataArray>"), std::string::npos);  // TimeValue
  // Node 5's displacement is (0, 0.02, 0) at the third time: it is the end of beam 2 (point 17).
  EXPECT_NE(vtu.find("\n0 0.02 0\n"), std::string::npos);

  traj.states[1].sig[0] = NAN;
  EXPECT_THROW(io::writeVtkSeries((dir.path / "bad").string(), m, traj), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir.path / "bad.pvd"));
}

TEST(HtmlAnimation, PageIsSelfContainedAndCarriesEveryFrame) {
  const core::Model m = cantilever();
  core::Trajectory traj = risingNode(m, 3, 5, 0.25, false);
  io::AnimationOptions o;
  o.title = "</script><b>";
  const std::string page = io::renderHtmlAnimation(m, traj, o);
  EXPECT_EQ(page.find("http:"), std::string::npos);
  EXPECT_EQ(page.find("https:"), std::string::npos);
  EXPECT_EQ(page.find(" src="), std::string::npos);
  EXPECT_EQ(page.find("</script><b>"), std::string::npos);  // the title cannot close the script
  EXPECT_NE(page.find("\"times\":[0,0.25,0.5,0.75,1]"), std::string::npos);
  EXPECT_NE(page.find("document.title = \"ok\""), std::string::npos);
  o.maxFrames = 3;
  const std::string thin = io::renderHtmlAnimation(m, traj, o);
  EXPECT_NE(thin.find("\"times\":[0,0.5,1]"), std::string::npos);
  EXPECT_THROW(io::renderHtmlAnimation(m, core::Trajectory{}), std::invalid_argument);
}
