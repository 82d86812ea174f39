// Mesh refinement as the reader applies it (io::ReadOptions::refine, core::refineModel): refining
// by 1 changes nothing; the total mass (each element's consistent mass matrix under a rigid
// translation, lumped masses added) is the original's to round-off; loads, fixes and masses stay
// on the original nodes under their labels; a released deformation stays released once; what
// cannot be split stays whole with a note; a bad refinement is an error naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {
std::string dat(const std::string& name) { return std::string(FLEXMB_SOURCE_DIR) + "/datfiles/" + name; }

io::ReadOptions refined(int parts) {
  io::ReadOptions o;
  o.refine = parts;
  return o;
}

// u^T M u summed over the elements for u a unit translation along axis `axis` of every position
// node, plus the lumped masses on that axis: the model's total mass.
double totalMass(const core::Model& m, int axis) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(m.nx);
  for (const core::Node& n : m.nodes)
    if (core::isTranslational(n.kind)) u[n.firstCoord + axis] = 1.0;
  double mass = 0.0;
  for (const core::ElementEntry& el : m.elements) {
    core::ElemVec x, ue;
    el.gather(m.x0, x);
    el.gather(u, ue);
    core::ElemMat M;
    el.impl->mass(x, el.inertia, M);
    mass += ue.dot(M * ue);
  }
  for (const core::LumpedMass& l : m.lumpedMasses) mass += l.value * u[l.coord] * u[l.coord];
  return mass;
}

bool hasNote(const core::Model& m, const std::string& text) {
  for (const std::string& n : m.notes)
    if (n.find(text) != std::string::npos) return true;
  return false;
}

const std::string kCantilever =
    "PLBEAM 1 1 2 3 4\n"
    "PLBEAM 2 3 4 5 6\n"
    "PLTRUSS 3 5 7\n"
    "X 1 0 0\nX 3 0.5 0\nX 5 1 0\nX 7 1 1\n"
    "FIX 1\nFIX 2\nFIX 7\n"
    "DYNE 1 1 2 3\nINPUTE 2 2\nDYNE 2 1 3\nDYNE 3 1\n"
    "END\nHALT\n"
    "EM 1 2.0\nEM 2 2.0\nESTIFF 1 1e6 10\nESTIFF 2 1e6 10\nESTIFF 3 1e5\nXM 5 0.5\nXF 5 0 -3\nXF 3 1 0\n"
    "END\nEND\n";
}  // namespace

TEST(MeshRefinement, ByOneChangesNothing) {
  const core::Model a = io::readDatFile(dat("straight_guidance.dat"));
  const core::Model b = io::readDatFile(dat("straight_guidance.dat"), refined(1));
  EXPECT_EQ(a.nx, b.nx);
  EXPECT_EQ(a.ne, b.ne);
  EXPECT_EQ(a.elements.size(), b.elements.size());
  EXPECT_EQ(a.numDofs(), b.numDofs());
  EXPECT_EQ((a.x0 - b.x0).norm(), 0.0);
  EXPECT_FALSE(hasNote(b, "refined"));
}

TEST(MeshRefinement, KeepsMassLoadsAndLabels) {
  const core::Model a = io::readDatFile(dat("straight_guidance.dat"));
  const double expected = 0.228 * 0.4 + 6.84 * 0.2;  // the flexures' and the body's rho A L
  EXPECT_NEAR(totalMass(a, 0), expected, 1e-14);
  for (int parts : {2, 3, 8}) {
    const core::Model r = io::readDatFile(dat("straight_guidance.dat"), refined(parts));
    for (int axis : {0, 1}) EXPECT_NEAR(totalMass(r, axis), expected, 1e-14) << parts << " parts";
    // 10 flexure beams split, the rigid body whole: 10 (parts - 1) new elements and position and
    // orientation nodes, each new node with 3 coordinates and each new element with 3 deformations.
    EXPECT_EQ(r.elements.size(), a.elements.size() + 10 * (parts - 1));
    EXPECT_EQ(r.nodes.size(), a.nodes.size() + 20 * (parts - 1));
    EXPECT_EQ(r.nx, a.nx + 30 * (parts - 1));
    EXPECT_TRUE(hasNote(r, "refined: every flexible beam split in " + std::to_string(parts) + " (" +
                               std::to_string(r.elements.size()) + " elements, " + std::to_string(r.nodes.size()) +
                               " nodes)"));
    // The original nodes first, under their labels, at their coordinates, with their roles.
    for (size_t i = 0; i < a.nodes.size(); ++i) {
      EXPECT_EQ(r.nodes[i].label, a.nodes[i].label);
      EXPECT_EQ(r.nodes[i].firstCoord, a.nodes[i].firstCoord);
    }
    EXPECT_EQ((r.x0.head(a.nx) - a.x0).norm(), 0.0);
    for (int i = 0; i < a.nx; ++i) EXPECT_EQ(r.xRole[i], a.xRole[i]);
    // The pulse stays on node 6 (the same coordinate), no force on a new node.
    ASSERT_EQ(r.timeForces.size(), 1u);
    EXPECT_EQ(r.timeForces[0].index, a.timeForces[0].index);
    EXPECT_EQ(r.f0.norm(), 0.0);
    // One released deformation per released original: e3 of element 5 in its last part, e2 of element
    // 15 in its first (which keeps the label 15), e3 of element 15 in its last.
    int released = 0;
    for (int e = 0; e < r.ne; ++e) released += r.eRole[e] == core::Role::Calculable;
    EXPECT_EQ(released, 3);
    const core::ElementEntry& e15 = r.elements[r.elementByLabel.at(15)];
    EXPECT_EQ(r.eRole[e15.firstDef + 1], core::Role::Calculable);
    EXPECT_EQ(r.eRole[e15.firstDef + 2], core::Role::Dynamic);
    EXPECT_EQ(r.nodes[e15.nodes[0]].label, 15);  // node p stays, node q is a new one
    EXPECT_GT(r.nodes[e15.nodes[2]].label, 116);
    EXPECT_EQ(r.numDofs(), 20 * parts - 3);  // every flexure bending but the 3 released
  }
}

TEST(MeshRefinement, SpatialBeamsKeepTheirMassAndLoads) {
  const core::Model a = io::readDatFile(dat("spatial/cross_spring_pivot_coarse.dat"));
  const core::Model r = io::readDatFile(dat("spatial/cross_spring_pivot_coarse.dat"), refined(3));
  for (int axis : {0, 1, 2}) EXPECT_NEAR(totalMass(r, axis), totalMass(a, axis), 1e-15);
  EXPECT_NEAR(totalMass(a, 2), 0.078 * (2 * std::sqrt(0.02) + 0.1), 1e-14);  // two leaves and the platform
  EXPECT_EQ((r.delf.head(a.nx) - a.delf).norm(), 0.0);
  EXPECT_EQ(r.delf.tail(r.nx - a.nx).norm(), 0.0);
  // New Euler-parameter nodes are unit quaternions, each with its own L2MIN1.
  int normalisations = 0;
  for (const core::ElementEntry& el : r.elements) normalisations += el.type->internal;
  int orientations = 0;
  for (const core::Node& n : r.nodes)
    if (n.kind == core::NodeKind::EulerParameters) {
      EXPECT_NEAR(r.x0.segment(n.firstCoord, 4).norm(), 1.0, 1e-15);
      ++orientations;
    }
  EXPECT_EQ(normalisations, orientations - 2);  // the two clamped ones have no unknown
  EXPECT_EQ(r.elements.size() - normalisations, 6u * 3 + 1);
}

TEST(MeshRefinement, LeavesWholeWhatCannotBeSplit) {
  const core::Model a = io::readDatString(kCantilever, "cantilever.dat");
  const core::Model r = io::readDatString(kCantilever, "cantilever.dat", refined(4));
  EXPECT_TRUE(hasNote(r, "refinement left PLBEAM 2: an input deformation (INPUTE) whole"));
  EXPECT_TRUE(hasNote(r, "refinement left PLTRUSS 3: a truss split in parts"));
  EXPECT_EQ(r.elements.size(), a.elements.size() + 3);
  EXPECT_EQ(r.numDofs(), a.numDofs() + 3 * 3);
  EXPECT_NEAR(totalMass(r, 0), totalMass(a, 0), 1e-14);
  EXPECT_NEAR(totalMass(a, 0), 2.0 * 1.0 + 0.5, 1e-14);
  EXPECT_EQ((r.f0.head(a.nx) - a.f0).norm(), 0.0);
  ASSERT_EQ(r.lumpedMasses.size(), a.lumpedMasses.size());
  // Initial values of a beam's deformations: zero ones are the reference (it is split), others not.
  for (const auto& [start, split] : {std::pair{"STARTDE 1 2 0 0\n", true}, std::pair{"STARTDE 1 2 0.01\n", false}}) {
    std::string text = kCantilever;
    text.replace(text.find("XM 5"), 0, start);
    const core::Model s = io::readDatString(text, "cantilever.dat", refined(4));
    EXPECT_EQ(s.elements.size(), a.elements.size() + (split ? 3 : 0)) << start;
    EXPECT_EQ(hasNote(s, "refinement left PLBEAM 1: initial values"), !split) << start;
  }
}

TEST(MeshRefinement, RefusesWhatItCannotDo) {
  for (int parts : {0, -2}) {
    try {
      io::readDatFile(dat("straight_guidance.dat"), refined(parts));
      ADD_FAILURE() << "refine " << parts << " was accepted";
    } catch (const io::DatError& e) {
      EXPECT_NE(std::string(e.what()).find("straight_guidance.dat"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("whole number >= 1"), std::string::npos) << e.what();
    }
  }
  const std::string restart =
      "PLBEAM 1 1 2 3 4\nX 1 0 0\nX 3 1 0\nFIX 1\nFIX 2\nDYNE 1\nEND\nHALT\n"
      "ESTIFF 1 1 1\nEM 1 1\nLENGTH0 1 1.0\nEND\nEND\n";
  EXPECT_THROW(io::readDatString(restart, "restart.dat", refined(2)), io::DatError);
  EXPECT_NO_THROW(io::readDatString(restart, "restart.dat"));
}
