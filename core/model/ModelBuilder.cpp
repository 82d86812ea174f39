#include "core/model/ModelBuilder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace flexmb::core {

// Every statement is recorded with its line and resolved in finalize(), so statements may come in
// any order (coordinates before the elements that define the nodes, for instance).
//
// Resolution rules (documented for the reader and its users):
//   * nodes get their kind from the first element slot that uses them; x indices in order of first
//     use; deformation indices in element order;
//   * coordinates (X/XY/BETA), stiffness, damping, inertia, lumped masses, prestress: a later
//     statement for the same item replaces an earlier one; forces (XF/FORCE, DELXF) add up;
//   * a role given twice for the same coordinate/deformation must agree (else error);
//   * q = DYNX coordinates then DYNE deformations, each in file order;
//   * every input coordinate/deformation gets a Rheonomic (inputX/inputE, in the order the roles
//     were declared) with x0 = the initial coordinate (0 for a deformation), v = a = 0 unless given;
//   * initial deformation values (E/ED/EDD/STARTDE) on an input deformation set its Rheonomic
//     x0/v/a; on a dynamic one they go to e0/ed0/edd0; on a fixed or released deformation only
//     zeros are accepted (they are then ignored).
struct ModelBuilder::Impl {
  std::string file;
  Dialect dialect = Dialect::Spacar2013;
  AnalysisSettings settings;

  struct ElemStmt {
    const ElementTypeInfo* type;
    int label;
    std::vector<int> nodes;
    int line;
    std::vector<double> vec = {};  // direction vector of spatial elements
  };
  struct CoordStmt {
    int node;
    std::vector<double> values;
    int line;
  };
  struct RoleStmt {
    int id;
    std::vector<int> comps;
    Role role;
    int line;
  };
  struct ScalarStmt {
    int id;
    double value;
    int line;
  };
  struct InertiaStmt {
    int element;
    double rhoA, rhoI;
    int line;
    std::vector<double> values = {};  // EM in the element type's layout (empty: rhoA, rhoI)
  };
  struct VectorStmt {
    int id;
    std::vector<double> values;
    int line;
  };
  struct CompFn {
    int id, comp;
    TimeFunctionPtr f;
    int line;
  };
  struct CompValues {
    int id, comp;
    std::optional<double> x, v, a;
    int line;
  };
  struct CompFns {
    int id, comp;
    TimeFunctionPtr x, v, a;
    int line;
  };
  struct CompScalar {
    int id, comp;
    double value;
    int line;
  };
  struct NoValuesStmt {  // EM / ESTIFF / EDAMP / ESIG with the element alone
    std::string keyword;
    int id;
    int line;
  };

  std::vector<ElemStmt> elements;
  std::vector<CoordStmt> coords;
  std::vector<CoordStmt> referenceCoords;  // XREF
  std::vector<RoleStmt> xRoles, eRoles;
  std::vector<ScalarStmt> masses;
  std::vector<InertiaStmt> inertias;
  std::vector<VectorStmt> stiffness, damping, forces, forceIncrements;
  std::vector<CompFn> timeForces, timeStresses, references;
  std::optional<std::pair<double, double>> gravity;
  double gravityZ = 0.0;
  std::vector<VectorStmt> nodeInertias;
  std::vector<CompValues> inputXValues, inputEValues, initialDeformations;
  std::vector<CompFns> inputXFunctions, inputEFunctions;
  std::vector<CompScalar> inputIncrements, coordinateRates, coordinateAccelerations;
  std::vector<VectorStmt> prestress;  // ESIG: a value per deformation
  std::vector<NoValuesStmt> noValues;
  std::vector<ScalarStmt> referenceLengths;
  std::vector<std::string> notes;
};

namespace {
// A reader note, each kept once (Model::notes).
void addOnce(std::vector<std::string>& notes, std::string note) {
  for (const auto& n : notes)
    if (n == note) return;
  notes.push_back(std::move(note));
}
}  // namespace

ModelBuilder::ModelBuilder(std::string sourceFile) : impl_(std::make_unique<Impl>()) {
  impl_->file = std::move(sourceFile);
}
ModelBuilder::~ModelBuilder() = default;

void ModelBuilder::addElement(const ElementTypeInfo& type, int label, std::span<const int> nodeLabels, int line) {
  impl_->elements.push_back({&type, label, {nodeLabels.begin(), nodeLabels.end()}, line});
}
void ModelBuilder::addElement(const ElementTypeInfo& type, int label, std::span<const int> nodeLabels,
                              std::span<const double> vector, int line) {
  impl_->elements.push_back(
      {&type, label, {nodeLabels.begin(), nodeLabels.end()}, line, {vector.begin(), vector.end()}});
}
void ModelBuilder::setElementInertia(int element, std::span<const double> values, int line) {
  impl_->inertias.push_back({element,
                             values.empty() ? 0.0 : values[0],
                             values.size() > 1 ? values[1] : 0.0,
                             line,
                             {values.begin(), values.end()}});
}
void ModelBuilder::setNodeInertia(int node, std::span<const double> values, int line) {
  impl_->nodeInertias.push_back({node, {values.begin(), values.end()}, line});
}
void ModelBuilder::setGravity(double gx, double gy, double gz, int line) {
  setGravity(gx, gy, line);
  impl_->gravityZ = gz;
}
void ModelBuilder::setCoordinates(int node, std::span<const double> values, int line) {
  impl_->coords.push_back({node, {values.begin(), values.end()}, line});
}
void ModelBuilder::setReferenceCoordinates(int node, std::span<const double> values, int line) {
  impl_->referenceCoords.push_back({node, {values.begin(), values.end()}, line});
}
void ModelBuilder::setCoordinateRole(int node, std::span<const int> comps, Role role, int line) {
  impl_->xRoles.push_back({node, {comps.begin(), comps.end()}, role, line});
}
void ModelBuilder::setDeformationRole(int element, std::span<const int> comps, Role role, int line) {
  impl_->eRoles.push_back({element, {comps.begin(), comps.end()}, role, line});
}
void ModelBuilder::setLumpedMass(int node, double value, int line) { impl_->masses.push_back({node, value, line}); }
void ModelBuilder::setElementInertia(int element, double rhoA, double rhoI, int line) {
  impl_->inertias.push_back({element, rhoA, rhoI, line});
}
void ModelBuilder::setStiffness(int element, std::span<const double> params, int line) {
  impl_->stiffness.push_back({element, {params.begin(), params.end()}, line});
}
void ModelBuilder::setDamping(int element, std::span<const double> params, int line) {
  impl_->damping.push_back({element, {params.begin(), params.end()}, line});
}
void ModelBuilder::addForce(int node, std::span<const double> comps, int line) {
  impl_->forces.push_back({node, {comps.begin(), comps.end()}, line});
}
void ModelBuilder::addForceIncrement(int node, std::span<const double> comps, int line) {
  impl_->forceIncrements.push_back({node, {comps.begin(), comps.end()}, line});
}
void ModelBuilder::addTimeForce(int node, int comp, TimeFunctionPtr f, int line) {
  impl_->timeForces.push_back({node, comp, std::move(f), line});
}
void ModelBuilder::setGravity(double gx, double gy, int /*line*/) {
  impl_->gravity = {gx, gy};
  impl_->gravityZ = 0.0;
}
void ModelBuilder::setInputCoordinate(int node, int comp, std::optional<double> x, std::optional<double> v,
                                      std::optional<double> a, int line) {
  impl_->inputXValues.push_back({node, comp, x, v, a, line});
}
void ModelBuilder::setInputCoordinateFunctions(int node, int comp, TimeFunctionPtr x, TimeFunctionPtr v,
                                               TimeFunctionPtr a, int line) {
  impl_->inputXFunctions.push_back({node, comp, std::move(x), std::move(v), std::move(a), line});
}
void ModelBuilder::setInputDeformationFunctions(int element, int comp, TimeFunctionPtr x, TimeFunctionPtr v,
                                                TimeFunctionPtr a, int line) {
  impl_->inputEFunctions.push_back({element, comp, std::move(x), std::move(v), std::move(a), line});
}
void ModelBuilder::setInputDeformation(int element, int comp, std::optional<double> x, std::optional<double> v,
                                       std::optional<double> a, int line) {
  impl_->inputEValues.push_back({element, comp, x, v, a, line});
}
void ModelBuilder::setInputIncrement(int node, int comp, double delta, int line) {
  impl_->inputIncrements.push_back({node, comp, delta, line});
}
void ModelBuilder::setInitialDeformation(int element, int comp, std::optional<double> e, std::optional<double> ed,
                                         std::optional<double> edd, int line) {
  impl_->initialDeformations.push_back({element, comp, e, ed, edd, line});
}
void ModelBuilder::setPrestress(int element, std::span<const double> values, int line) {
  impl_->prestress.push_back({element, {values.begin(), values.end()}, line});
}
void ModelBuilder::noValues(const std::string& keyword, int element, int line) {
  impl_->noValues.push_back({keyword, element, line});
}
void ModelBuilder::setCoordinateRate(int node, int comp, double v, int line) {
  impl_->coordinateRates.push_back({node, comp, v, line});
}
void ModelBuilder::setCoordinateAcceleration(int node, int comp, double a, int line) {
  impl_->coordinateAccelerations.push_back({node, comp, a, line});
}
void ModelBuilder::setReferenceLength(int element, double length0, int line) {
  impl_->referenceLengths.push_back({element, length0, line});
}
void ModelBuilder::addNote(std::string note) { addOnce(impl_->notes, std::move(note)); }
void ModelBuilder::addTimeStress(int element, int comp, TimeFunctionPtr f, int line) {
  impl_->timeStresses.push_back({element, comp, std::move(f), line});
}
void ModelBuilder::setReference(int element, int comp, TimeFunctionPtr f, int line) {
  impl_->references.push_back({element, comp, std::move(f), line});
}
AnalysisSettings& ModelBuilder::settings() { return impl_->settings; }
void ModelBuilder::setDialect(Dialect d) { impl_->dialect = d; }

namespace {

std::string num(double v) {
  std::ostringstream o;
  o.precision(12);
  o << v;
  return o.str();
}

// What a node of a kind is called in messages: "position", "orientation", "warping".
const char* kindWord(NodeKind k) {
  return isTranslational(k) ? "position" : k == NodeKind::Warping ? "warping" : "orientation";
}

// Name of an element slot, as in the reader's messages: "node p", "orientation q", "warping p".
std::string slotName(const ElementTypeInfo& type, size_t slot) {
  int idx = 0;
  for (size_t s = 0; s < slot; ++s)
    if (type.slots[s] == type.slots[slot]) ++idx;
  const NodeKind k = type.slots[slot];
  return std::string(isTranslational(k)       ? "node "
                     : k == NodeKind::Warping ? "warping "
                                              : "orientation ") +
         static_cast<char>('p' + std::min(idx, 9));
}

// "12, 15, 18": the lines of statements a note names, the first eight and how many more.
std::string lineList(const std::vector<int>& lines) {
  std::string s;
  const size_t shown = std::min<size_t>(lines.size(), 8);
  for (size_t i = 0; i < shown; ++i) (s += i ? ", " : "") += std::to_string(lines[i]);
  if (lines.size() > shown) ((s += " and ") += std::to_string(lines.size() - shown)) += " more";
  return s;
}

// "1st", "2nd", "7th": the position of a value in a statement.
std::string ordinal(size_t i) {
  const char* suffix = i % 10 == 1 && i % 100 != 11   ? "st"
                       : i % 10 == 2 && i % 100 != 12 ? "nd"
                       : i % 10 == 3 && i % 100 != 13 ? "rd"
                                                      : "th";
  return std::to_string(i) + suffix;
}

int slotsCoords(const ElementTypeInfo& type) {
  int n = 0;
  for (NodeKind k : type.slots) n += nodeKindDim(k);
  return n;
}

struct Resolver {
  Model& m;
  // Where each node was first used: element index and slot.
  std::vector<std::pair<int, int>> firstUse;
  std::vector<int> xRoleLine, eRoleLine;

  [[noreturn]] static void fail(int line, const std::string& msg) { throw ModelError(line, msg); }

  std::string elemName(int ei) const {
    return m.elements[ei].type->keyword + " " + std::to_string(m.elements[ei].label);
  }

  // consequence: what the statement would lose on a node no element uses ("the load acts on nothing").
  int node(int label, int line, const char* consequence = nullptr) const {
    auto it = m.nodeByLabel.find(label);
    if (it == m.nodeByLabel.end())
      fail(line, "node " + std::to_string(label) + " is not used by any element" +
                     (consequence ? std::string(": ") + consequence : std::string()));
    return it->second;
  }
  int element(int label, int line) const {
    auto it = m.elementByLabel.find(label);
    if (it == m.elementByLabel.end()) fail(line, "element " + std::to_string(label) + " is not defined");
    return it->second;
  }
  std::string nodeDescription(int ni) const {
    const Node& n = m.nodes[ni];
    const char* what = "";
    switch (n.kind) {
      case NodeKind::Position:
        what = "a position node (components 1..2: x, y)";
        break;
      case NodeKind::Orientation:
        what = "an orientation node (component 1: angle)";
        break;
      case NodeKind::SpatialPosition:
        what = "a position node (components 1..3: x, y, z)";
        break;
      case NodeKind::EulerParameters:
        what = "an orientation node (components 1..4: Euler parameters lambda0..lambda3)";
        break;
      case NodeKind::Warping:
        what = "a warping node (component 1: rate of twist)";
        break;
    }
    return "node " + std::to_string(n.label) + " is " + what;
  }
  int x(int nodeLabel, int comp, int line) const {
    const int ni = node(nodeLabel, line);
    const Node& n = m.nodes[ni];
    if (comp < 1 || comp > n.dim())
      fail(line, "component " + std::to_string(comp) + " out of range: " + nodeDescription(ni));
    return n.firstCoord + comp - 1;
  }
  std::string elementDescription(int ei) const {
    const ElementEntry& el = m.elements[ei];
    std::string s = elemName(ei) + " has " + std::to_string(el.type->numDeformations()) + " deformation" +
                    (el.type->numDeformations() == 1 ? "" : "s") + " (";
    for (int i = 0; i < el.type->numDeformations(); ++i)
      s += (i ? ", " : "") + std::to_string(i + 1) + " " + el.type->deformationNames[i];
    return s + ")";
  }
  int e(int elemLabel, int comp, int line) const {
    const int ei = element(elemLabel, line);
    const ElementEntry& el = m.elements[ei];
    if (comp < 1 || comp > el.type->numDeformations())
      fail(line, "component " + std::to_string(comp) + " out of range: " + elementDescription(ei));
    return el.firstDef + comp - 1;
  }
};

}  // namespace

// finalize() in its phases, each a function below, in the order they depend on each other: the
// topology (elements, nodes, coordinate and deformation indices), the initial coordinates, the
// roles, the automatic L2MIN1 elements, the element objects with (restart) their references, then
// what refers to them: constitutive matrices, inertia, loads, stresses, rheonomic inputs and the
// initial deformations.
struct ModelBuilder::Finalizer {
  using R = Resolver;
  Impl& in;
  Model m;
  Resolver r{m, {}, {}, {}};
  std::vector<int> inputXOrder, inputEOrder;  // input coordinates and deformations, as declared
  std::map<int, int> normalisationOf;         // orientation node index -> its L2MIN1 element index
  std::map<int, size_t> inputXAt, inputEAt;   // x / e index of an input -> its Rheonomic

  explicit Finalizer(Impl& impl) : in(impl) {
    m.sourceFile = in.file;
    m.dialect = in.dialect;
    m.settings = in.settings;
  }
  Finalizer(const Finalizer&) = delete;  // r refers to m
  Finalizer& operator=(const Finalizer&) = delete;

  void elements();
  int slotNode(const Impl::ElemStmt& st, size_t s, int ei, const ElementEntry& el);
  void initialCoordinates();
  void referenceCoordinates();
  void coordinateRoles();
  void deformationRoles();
  void normalisationElements();
  void elementObjects(const ElementOptions& options);
  void restartReferences();
  void linesWithoutValues();
  void constitutive(const std::vector<Impl::VectorStmt>& stmts, bool damping);
  void elementInertia();
  void nodeInertia();
  void lumpedMasses();
  void nodalLoads(const std::vector<Impl::VectorStmt>& stmts, Eigen::VectorXd& f, bool increment,
                  std::map<int, size_t>& momentAt);
  void loads();
  void stresses();
  void rheonomicInputs();
  Rheonomic& inputX(int node, int comp, int line);
  Rheonomic& inputE(int element, int comp, int line);
  static void setValues(Rheonomic& rh, const Impl::CompValues& st);
  void initialDeformations();
  void note(std::string text) { addOnce(in.notes, std::move(text)); }
  void requireStiffness(int ei, size_t given, int line);
  void refuseStiffnessLostToAShortLine(int ei, const std::vector<double>& given, const DefMat& S, int line);
  void ignoreExtras(const std::string& keyword, int ei, size_t given, size_t own,
                    const std::vector<ParameterSpec>& ignored, int line);
  void ignoredValueNotes();
  struct Ignored {  // values read and ignored: the statements' lines and what the note says
    std::vector<int> lines;
    std::string what;
  };
  std::map<std::string, Ignored> ignoredValues;  // by "keyword element-type"
};

Model ModelBuilder::finalize(const ElementOptions& options) {
  Finalizer f(*impl_);
  f.elements();
  f.initialCoordinates();
  f.referenceCoordinates();
  f.coordinateRoles();
  f.deformationRoles();
  f.normalisationElements();
  f.elementObjects(options);
  f.restartReferences();
  f.linesWithoutValues();
  f.constitutive(impl_->stiffness, false);
  f.constitutive(impl_->damping, true);
  f.elementInertia();
  f.nodeInertia();
  f.lumpedMasses();
  f.loads();
  f.stresses();
  f.rheonomicInputs();
  f.initialDeformations();
  f.ignoredValueNotes();
  f.m.notes = impl_->notes;  // the reader's and the phases' (coordinateRoles)
  return std::move(f.m);
}

void ModelBuilder::Finalizer::elements() {
  if (in.elements.empty()) R::fail(0, "the model defines no elements");

  // Elements, nodes (kind and x indices in order of first use), deformation indices.
  const Impl::ElemStmt* firstOfKind[2] = {nullptr, nullptr};  // first planar, first spatial
  for (const auto& st : in.elements) {
    if (!st.type) R::fail(st.line, "element without a type");
    const ElementTypeInfo& type = *st.type;
    if (st.label <= 0) R::fail(st.line, "element label must be a positive integer, found " + std::to_string(st.label));
    if (auto it = m.elementByLabel.find(st.label); it != m.elementByLabel.end())
      R::fail(st.line, "element " + std::to_string(st.label) + " is already defined (" + r.elemName(it->second) +
                           " at line " + std::to_string(m.elements[it->second].line) + ")");
    if (st.nodes.size() != type.slots.size())
      R::fail(st.line, type.keyword + " needs " + std::to_string(type.slots.size()) + " nodes, found " +
                           std::to_string(st.nodes.size()));
    if (st.vec.size() != type.vector.size())
      R::fail(st.line, type.keyword + " " + std::to_string(st.label) + " needs " + std::to_string(type.vector.size()) +
                           " direction components after its nodes, found " + std::to_string(st.vec.size()));
    for (double v : st.vec)
      if (!std::isfinite(v)) R::fail(st.line, "direction vector is not finite");
    // A model is planar or spatial.
    const bool spatialType = isSpatial(type.slots.front());
    if (!firstOfKind[spatialType]) firstOfKind[spatialType] = &st;
    if (firstOfKind[!spatialType]) {
      const Impl::ElemStmt* o = firstOfKind[!spatialType];
      const Impl::ElemStmt* planar = spatialType ? o : &st;
      const Impl::ElemStmt* spatial = spatialType ? &st : o;
      R::fail(st.line, "planar and spatial elements cannot be mixed in one model: planar " + planar->type->keyword +
                           " " + std::to_string(planar->label) + " (line " + std::to_string(planar->line) +
                           ") and spatial " + spatial->type->keyword + " " + std::to_string(spatial->label) +
                           " (line " + std::to_string(spatial->line) + ")");
    }
    m.spatial = spatialType;
    const int ei = static_cast<int>(m.elements.size());
    ElementEntry el;
    el.label = st.label;
    el.type = &type;
    el.line = st.line;
    el.vec = st.vec;
    for (size_t s = 0; s < st.nodes.size(); ++s) {
      const int label = st.nodes[s];
      if (label <= 0) R::fail(st.line, "node label must be a positive integer, found " + std::to_string(label));
      for (size_t s2 = 0; s2 < s; ++s2)
        if (st.nodes[s2] == label)
          R::fail(st.line, "node " + std::to_string(label) + " appears twice in " + type.keyword + " " +
                               std::to_string(st.label) + " (" + slotName(type, s2) + " and " + slotName(type, s) +
                               ")");
      const int ni = slotNode(st, s, ei, el);
      el.nodes.push_back(ni);
      for (int c = 0; c < m.nodes[ni].dim(); ++c) el.coords.push_back(m.nodes[ni].firstCoord + c);
    }
    el.firstDef = m.ne;
    m.ne += type.numDeformations();
    for (int d = 0; d < type.numDeformations(); ++d) m.eOwnerElement.push_back(ei);
    m.elementByLabel[st.label] = ei;
    m.elements.push_back(std::move(el));
  }
}

// The node of slot s of element statement st (element index ei, entry el being built): created at
// its first use (kind from the slot, x indices next in order), else checked against its kind.
int ModelBuilder::Finalizer::slotNode(const Impl::ElemStmt& st, size_t s, int ei, const ElementEntry& el) {
  const ElementTypeInfo& type = *st.type;
  const int label = st.nodes[s];
  const NodeKind kind = type.slots[s];
  auto it = m.nodeByLabel.find(label);
  if (it == m.nodeByLabel.end()) {
    const int ni = static_cast<int>(m.nodes.size());
    Node n;
    n.label = label;
    n.kind = kind;
    n.firstCoord = m.nx;
    n.line = st.line;
    m.nodes.push_back(n);
    m.nodeByLabel[label] = ni;
    r.firstUse.push_back({ei, static_cast<int>(s)});
    m.nx += n.dim();
    for (int c = 0; c < n.dim(); ++c) m.xOwnerNode.push_back(ni);
    return ni;
  }
  const int ni = it->second;
  const Node& n = m.nodes[ni];
  if (n.kind != kind) {
    const auto [fe, fs] = r.firstUse[ni];
    const ElementEntry& first = fe == ei ? el : m.elements[fe];
    auto article = [](NodeKind k) { return std::string(kindWord(k)[0] == 'o' ? "an " : "a ") + kindWord(k); };
    R::fail(st.line, "node " + std::to_string(label) + " is used as " + article(kind) + " node here (" + type.keyword +
                         " " + std::to_string(st.label) + ", " + slotName(type, s) + ") but as " + article(n.kind) +
                         " node by " + first.type->keyword + " " + std::to_string(first.label) + " (" +
                         slotName(*first.type, fs) + ") at line " + std::to_string(first.line));
  }
  return ni;
}

void ModelBuilder::Finalizer::initialCoordinates() {
  m.x0 = Eigen::VectorXd::Zero(m.nx);
  for (const Node& n : m.nodes)
    if (n.kind == NodeKind::EulerParameters) m.x0[n.firstCoord] = 1.0;  // default 1 0 0 0
  // Extras that change nothing are notes (SPACAR writers emit them: oopspa an X line for every
  // keypoint's position node, used or not); what would change the model is an error or a warning
  // (io/README.md, "Harmless extras and silent mistakes").
  std::vector<char> placed(m.nodes.size(), 0);
  for (const auto& st : in.coords) {
    if (!m.nodeByLabel.count(st.node)) {
      note("coordinates of node " + std::to_string(st.node) + " (line " + std::to_string(st.line) + "): node " +
           std::to_string(st.node) + " is not used by any element; ignored");
      continue;
    }
    const int ni = r.node(st.node, st.line);
    placed[ni] = 1;
    const Node& n = m.nodes[ni];
    if (static_cast<int>(st.values.size()) != n.dim())
      R::fail(st.line, r.nodeDescription(ni) + ": expected " + std::to_string(n.dim()) + " coordinate" +
                           (n.dim() == 1 ? "" : "s") + ", found " + std::to_string(st.values.size()));
    for (int c = 0; c < n.dim(); ++c) {
      if (!std::isfinite(st.values[c])) R::fail(st.line, "coordinate is not finite");
      m.x0[n.firstCoord + c] = st.values[c];
    }
  }
  // A position node no coordinate statement places sits at the origin (SPACAR's default, [C S95]:
  // nodes default to 0 0 0): legal, but usually a forgotten X line that folds an element.
  for (size_t ni = 0; ni < m.nodes.size(); ++ni) {
    const Node& n = m.nodes[ni];
    if (placed[ni] || !isTranslational(n.kind)) continue;
    const auto [fe, fs] = r.firstUse[ni];
    m.warnings.push_back(
        "node " + std::to_string(n.label) + " (" + slotName(*m.elements[fe].type, fs) + " of " + r.elemName(fe) +
        ", line " + std::to_string(m.elements[fe].line) + ") has no X line: it is placed at the origin (" +
        (n.kind == NodeKind::SpatialPosition ? "0, 0, 0" : "0, 0") + "), as SPACAR does; write X " +
        std::to_string(n.label) + (n.kind == NodeKind::SpatialPosition ? " 0 0 0" : " 0 0") + " if that is meant");
  }
}

// XREF (flexmb extension, spatial restart echoes): where the elements are created, when X gives the
// current configuration; every other node's reference is its X.
void ModelBuilder::Finalizer::referenceCoordinates() {
  m.xRef = m.x0;
  for (const auto& st : in.referenceCoords) {
    const int ni = r.node(st.node, st.line, "its reference coordinates would belong to nothing");
    const Node& n = m.nodes[ni];
    if (static_cast<int>(st.values.size()) != n.dim())
      R::fail(st.line, r.nodeDescription(ni) + ": expected " + std::to_string(n.dim()) + " reference coordinate" +
                           (n.dim() == 1 ? "" : "s") + ", found " + std::to_string(st.values.size()));
    for (int c = 0; c < n.dim(); ++c) {
      if (!std::isfinite(st.values[c])) R::fail(st.line, "reference coordinate is not finite");
      m.xRef[n.firstCoord + c] = st.values[c];
    }
  }
}

void ModelBuilder::Finalizer::coordinateRoles() {
  m.xRole.assign(m.nx, Role::Calculable);
  r.xRoleLine.assign(m.nx, 0);
  for (const auto& st : in.xRoles) {
    // SPACAR accepts FIX on a node no element uses (SPACAR Light writes one for the warping node
    // of every fixed node, BEAMW or not; oopspa `FIX n 1`): nothing to fix, so a note. An input
    // or a degree of freedom there would be lost: an error.
    if (st.role == Role::Fixed && !m.nodeByLabel.count(st.id)) {
      std::string comps;
      for (int c : st.comps) (comps += ' ') += std::to_string(c);
      note("FIX " + std::to_string(st.id) + comps + " (line " + std::to_string(st.line) + "): node " +
           std::to_string(st.id) + " is not used by any element; ignored (nothing is fixed)");
      continue;
    }
    const int ni = r.node(st.id, st.line);
    const Node& n = m.nodes[ni];
    std::vector<int> comps = st.comps;
    if (comps.empty())
      for (int c = 1; c <= n.dim(); ++c) comps.push_back(c);
    for (int c : comps) {
      const int xi = r.x(st.id, c, st.line);
      if (r.xRoleLine[xi] != 0 && m.xRole[xi] != st.role)
        R::fail(st.line, "cannot make " + m.coordName(xi) + " " + roleName(st.role) + ": it was made " +
                             roleName(m.xRole[xi]) + " at line " + std::to_string(r.xRoleLine[xi]));
      if (r.xRoleLine[xi] == 0) {
        r.xRoleLine[xi] = st.line;
        m.xRole[xi] = st.role;
        if (st.role == Role::Dynamic) m.dofs.push_back({false, xi});
        if (st.role == Role::Input) inputXOrder.push_back(xi);
      }
    }
  }
  // A warping coordinate no FIX, INPUTX or DYNX named is a degree of freedom: the only reading under
  // which SPACAR Light's BEAMW files (warping nodes fixed at clamps, e7 e8 never named) count square
  // (core/elements/BEAMW.md section 1). After the DYNX coordinates, in node order.
  for (const Node& n : m.nodes)
    if (n.kind == NodeKind::Warping && r.xRoleLine[n.firstCoord] == 0) {
      m.xRole[n.firstCoord] = Role::Dynamic;
      m.dofs.push_back({false, n.firstCoord});
    }
}

void ModelBuilder::Finalizer::deformationRoles() {
  m.eRole.assign(m.ne, Role::Fixed);
  r.eRoleLine.assign(m.ne, 0);
  // Deformations that are always released (BEAMW's warping deformations): calculable, whatever
  // the file says (core/elements/BEAMW.md section 1).
  for (const ElementEntry& el : m.elements)
    for (int d : el.type->alwaysReleased) m.eRole[el.firstDef + d] = Role::Calculable;
  for (const auto& st : in.eRoles) {
    const int ei = r.element(st.id, st.line);
    const ElementTypeInfo& type = *m.elements[ei].type;
    std::vector<int> comps = st.comps;
    if (comps.empty())  // all of the element's deformations that can take a role
      for (int c = 1; c <= type.numDeformations(); ++c)
        if (!type.isAlwaysReleased(c - 1)) comps.push_back(c);
    for (int c : comps) {
      const int di = r.e(st.id, c, st.line);
      if (type.isAlwaysReleased(c - 1)) {
        if (st.role == Role::Calculable) continue;  // RLSE: what it is anyway
        R::fail(st.line, m.deformationName(di) + " is always released (calculable): " + type.keyword +
                             " deformations 7 and 8 carry the warping stress and cannot be " +
                             (st.role == Role::Dynamic ? "DYNE" : "INPUTE") +
                             "; FIX or INPUTX the warping node to restrain or prescribe warping");
      }
      if (r.eRoleLine[di] != 0 && m.eRole[di] != st.role)
        R::fail(st.line, "cannot make " + m.deformationName(di) + " " + roleName(st.role) + ": it was made " +
                             roleName(m.eRole[di]) + " at line " + std::to_string(r.eRoleLine[di]));
      if (r.eRoleLine[di] == 0) {
        r.eRoleLine[di] = st.line;
        m.eRole[di] = st.role;
        if (st.role == Role::Dynamic) m.dofs.push_back({true, di});
        if (st.role == Role::Input) inputEOrder.push_back(di);
      }
    }
  }
}

void ModelBuilder::Finalizer::normalisationElements() {
  // L2MIN1: the normalisation constraint of every orientation node with a calculable parameter
  // (with all four parameters known it has no unknown and drops out). Labels follow the user's.
  {
    int label = m.elementByLabel.empty() ? 0 : m.elementByLabel.rbegin()->first;
    for (size_t ni = 0; ni < m.nodes.size(); ++ni) {
      const Node& n = m.nodes[ni];
      if (n.kind != NodeKind::EulerParameters) continue;
      bool calculable = false;
      for (int c = 0; c < 4; ++c) calculable |= m.xRole[n.firstCoord + c] == Role::Calculable;
      if (!calculable) continue;
      ElementEntry el;
      el.label = ++label;
      el.type = &normalisationType();
      el.line = n.line;
      el.nodes = {static_cast<int>(ni)};
      for (int c = 0; c < 4; ++c) el.coords.push_back(n.firstCoord + c);
      el.firstDef = m.ne++;
      m.eOwnerElement.push_back(static_cast<int>(m.elements.size()));
      m.eRole.push_back(Role::Fixed);
      r.eRoleLine.push_back(0);
      normalisationOf[static_cast<int>(ni)] = static_cast<int>(m.elements.size());
      m.elements.push_back(std::move(el));
    }
  }
}

void ModelBuilder::Finalizer::elementObjects(const ElementOptions& options) {
  for (size_t ei = 0; ei < m.elements.size(); ++ei) {
    ElementEntry& el = m.elements[ei];
    const int nc = slotsCoords(*el.type);
    if (nc > kMaxElemCoords || el.type->numDeformations() > kMaxElemDefs)
      R::fail(el.line, el.type->keyword + ": element type exceeds the fixed element capacity");
    ElemVec x0e(nc);
    for (int c = 0; c < nc; ++c) x0e[c] = m.xRef[el.coords[c]];
    if (!el.type->create && !el.type->createWithVector)
      R::fail(el.line, el.type->keyword + ": element type cannot be created");
    try {
      std::unique_ptr<Element> impl = el.type->createWithVector
                                          ? el.type->createWithVector(x0e, in.elements[ei].vec.data(), options)
                                          : el.type->create(x0e, options);
      if (!impl) R::fail(el.line, el.type->keyword + ": element could not be created");
      el.impl = std::move(impl);
    } catch (const ModelError&) {
      throw;
    } catch (const std::exception& ex) {
      R::fail(el.line, r.elemName(static_cast<int>(ei)) + ": " + ex.what());
    }
    el.S = DefMat::Zero(el.type->numDeformations(), el.type->numDeformations());
    el.Sd = el.S;
  }
}

void ModelBuilder::Finalizer::restartReferences() {
  // Restart state (LENGTH0 given): X is the current configuration; every element's reference is
  // re-derived so that its deformations there are the given E values (0 where not given), with
  // the reference length from LENGTH0 where given.
  m.restartState = !in.referenceLengths.empty();
  if (m.restartState) {
    std::vector<double> length0(m.elements.size(), 0.0);
    for (const auto& st : in.referenceLengths) {
      const int ei = r.element(st.id, st.line);
      if (!(st.value > 0.0) || !std::isfinite(st.value))
        R::fail(st.line, "the reference length of " + r.elemName(ei) + " must be positive, found " + num(st.value));
      length0[ei] = st.value;
    }
    Eigen::VectorXd eAt = Eigen::VectorXd::Zero(m.ne);
    for (const auto& st : in.inputEValues)
      if (st.x) eAt[r.e(st.id, st.comp, st.line)] = *st.x;
    for (const auto& st : in.initialDeformations)
      if (st.x) eAt[r.e(st.id, st.comp, st.line)] = *st.x;
    for (size_t ei = 0; ei < m.elements.size(); ++ei) {
      ElementEntry& el = m.elements[ei];
      const int nc = slotsCoords(*el.type);
      ElemVec xe(nc);
      for (int c = 0; c < nc; ++c) xe[c] = m.x0[el.coords[c]];
      DefVec ee(el.type->numDeformations());
      for (int d = 0; d < el.type->numDeformations(); ++d)
        ee[d] = m.eRole[el.firstDef + d] == Role::Fixed ? 0.0 : eAt[el.firstDef + d];
      try {
        std::const_pointer_cast<Element>(el.impl)->setReference(xe, ee, length0[ei]);
      } catch (const std::exception& ex) {
        R::fail(el.line, r.elemName(static_cast<int>(ei)) + " (restart reference from LENGTH0/E): " + ex.what());
      }
    }
  }
}

void ModelBuilder::Finalizer::constitutive(const std::vector<Impl::VectorStmt>& stmts, bool damping) {
  for (const auto& st : stmts) {
    const int ei = r.element(st.id, st.line);
    ElementEntry& el = m.elements[ei];
    const auto& layout = el.type->stiffness;
    const size_t accepted = layout.size() + el.type->ignoredStiffness.size();
    // Spatial elements: trailing parameters may be omitted (0), as SPACAR files do.
    const bool tooFew =
        isSpatial(el.type->slots.front()) ? st.values.empty() && !layout.empty() : st.values.size() != layout.size();
    if (tooFew || st.values.size() > accepted) {
      std::string names;
      for (size_t i = 0; i < layout.size(); ++i) names += (i ? ", " : "") + layout[i].name;
      R::fail(st.line, r.elemName(ei) + " takes " + std::to_string(layout.size()) + " " +
                           (damping ? "damping" : "stiffness") + " parameter" + (layout.size() == 1 ? "" : "s") + " (" +
                           names + "), found " + std::to_string(st.values.size()));
    }
    if (!damping) requireStiffness(ei, st.values.size(), st.line);
    for (double v : st.values)
      if (!std::isfinite(v)) R::fail(st.line, "parameter is not finite");
    ignoreExtras(damping ? "EDAMP" : "ESTIFF", ei, st.values.size(), layout.size(), el.type->ignoredStiffness, st.line);
    const std::vector<double> own(
        st.values.begin(), st.values.begin() + static_cast<std::ptrdiff_t>(std::min(st.values.size(), layout.size())));
    DefMat S = DefMat::Zero(el.type->numDeformations(), el.type->numDeformations());
    el.impl->constitutive(own, S);
    if (!damping && own.size() < layout.size()) refuseStiffnessLostToAShortLine(ei, own, S, st.line);
    if (damping) {
      el.Sd = S;
      el.hasDamping = true;
      el.dampingParams = own;
    } else {
      el.S = S;
      el.hasStiffness = true;
      el.stiffnessParams = own;
    }
  }
}

// Values other programs write after an element's own layout (SPACAR Light and oopspa: BEAMW's
// section layout for every beam and truss) are read and ignored; one note per keyword and element
// type (ignoredValueNotes) names the file and the lines.
void ModelBuilder::Finalizer::ignoreExtras(const std::string& keyword, int ei, size_t given, size_t own,
                                           const std::vector<ParameterSpec>& ignored, int line) {
  if (given <= own) return;
  const ElementTypeInfo& type = *m.elements[ei].type;
  Ignored& ig = ignoredValues[keyword + " " + type.keyword];
  if (ig.lines.empty()) {
    std::string names;
    for (size_t i = 0; own + i < given; ++i) names += (i ? ", " : "") + ignored[i].name;
    ig.what = keyword + " on " + type.keyword + ": " + std::to_string(given) + " values, the " + ordinal(own + 1) +
              (given > own + 1 ? " to " + ordinal(given) : "") + " (" + names + ") " +
              (given > own + 1 ? "have" : "has") + " no meaning for " + type.keyword +
              " (written by SPACAR Light and oopspa for BEAMW's section layout) and " +
              (given > own + 1 ? "are" : "is") + " ignored";
  }
  ig.lines.push_back(line);
}

void ModelBuilder::Finalizer::ignoredValueNotes() {
  for (const auto& [key, ig] : ignoredValues)
    note(in.file + ":" + std::to_string(ig.lines.front()) + ": " + ig.what +
         (ig.lines.size() > 1 ? " (lines " + lineList(ig.lines) + ")" : ""));
}

// EM, ESTIFF, EDAMP or ESIG with the element number and no values: oopspa's writer gives every
// element such a line, also those without the property, and SPACAR runs those files. The line sets
// nothing (the element keeps no stiffness, damping, inertia or prestress from it, and a full line
// for the element, before or after, keeps its values), so it is a note, one per keyword naming
// the elements and the lines (io/README.md, "Harmless extras"). The element must exist. These
// lines never reach constitutive(): ModelBuilder::noValues keeps them apart.
void ModelBuilder::Finalizer::linesWithoutValues() {
  std::vector<std::string> keywords;  // in the order of their first such line
  std::map<std::string, std::pair<std::vector<int>, std::vector<int>>> byKeyword;  // element labels, lines
  for (const auto& st : in.noValues) {
    r.element(st.id, st.line);
    auto [it, fresh] = byKeyword.try_emplace(st.keyword);
    if (fresh) keywords.push_back(st.keyword);
    std::vector<int>& labels = it->second.first;
    if (std::find(labels.begin(), labels.end(), st.id) == labels.end()) labels.push_back(st.id);
    it->second.second.push_back(st.line);
  }
  for (const std::string& keyword : keywords) {
    const auto& [labels, lines] = byKeyword.at(keyword);
    std::string labelText;
    for (size_t i = 0; i < labels.size(); ++i) (labelText += i ? ", " : "") += std::to_string(labels[i]);
    const bool several = lines.size() > 1;
    note(in.file + ":" + std::to_string(lines.front()) + ": " + keyword + " without values for element" +
         (labels.size() > 1 ? "s " : " ") + labelText + (several ? " (lines " + lineList(lines) + ")" : "") +
         ": nothing set, as if the line" + (several ? "s were" : " were") +
         " absent (oopspa writes such lines for elements without the property)");
  }
}

// A short ESTIFF line (trailing values omitted count as 0, as SPACAR files write them) must not
// leave a dynamic deformation without stiffness: that deformation would move freely (a flexure
// platform sagging by millimetres) with exit 0. An explicit 0 stays legal. The deformations the
// omitted values reach are found by giving them a nonzero value.
void ModelBuilder::Finalizer::refuseStiffnessLostToAShortLine(int ei, const std::vector<double>& given, const DefMat& S,
                                                              int line) {
  const ElementEntry& el = m.elements[ei];
  const ElementTypeInfo& type = *el.type;
  std::vector<double> full = given;
  full.resize(type.stiffness.size(), 1.0);
  DefMat withAll = DefMat::Zero(type.numDeformations(), type.numDeformations());
  el.impl->constitutive(full, withAll);
  for (int d = 0; d < type.numDeformations(); ++d) {
    const int di = el.firstDef + d;
    if (m.eRole[di] != Role::Dynamic) continue;
    if (S.row(d).cwiseAbs().maxCoeff() != 0.0 || withAll.row(d).cwiseAbs().maxCoeff() == 0.0) continue;
    std::string missing;
    for (size_t i = given.size(); i < type.stiffness.size(); ++i)
      missing += (i > given.size() ? ", " : "") + type.stiffness[i].name;
    R::fail(line, "ESTIFF of " + r.elemName(ei) + " gives " + std::to_string(given.size()) + " of its " +
                      std::to_string(type.stiffness.size()) + " stiffness values: without " + missing +
                      ", the dynamic " + m.deformationName(di) +
                      " has no stiffness and moves freely; give the values (write 0 where " + "no stiffness is meant)");
  }
}

// An ESTIFF with fewer values than the type requires (BEAMW without ECw): an error naming the first
// missing value.
void ModelBuilder::Finalizer::requireStiffness(int ei, size_t given, int line) {
  const ElementTypeInfo& type = *m.elements[ei].type;
  if (given >= static_cast<size_t>(type.requiredStiffness)) return;
  const ParameterSpec& p = type.stiffness[given];
  std::string names;
  for (size_t i = 0; i < type.stiffness.size(); ++i) names += (i ? ", " : "") + type.stiffness[i].name;
  R::fail(line, r.elemName(ei) + " takes " + std::to_string(type.requiredStiffness) + " stiffness parameters (" +
                    names + "), found " + std::to_string(given) + ": the " + ordinal(given + 1) + " value, " + p.name +
                    " (" + p.meaning + "), is missing" +
                    (p.name == "ECw" ? " (write 0 for a section without warping stiffness, such as a circle)" : ""));
}

// EMASS / EM: distributed inertia in the element type's layout.
void ModelBuilder::Finalizer::elementInertia() {
  for (const auto& st : in.inertias) {
    const int ei = r.element(st.element, st.line);
    if (!(st.rhoA >= 0.0) || !std::isfinite(st.rhoA))
      R::fail(st.line, "negative mass per unit length " + num(st.rhoA) + " for " + r.elemName(ei));
    if (!(st.rhoI >= 0.0) || !std::isfinite(st.rhoI))
      R::fail(st.line, "negative rotary inertia per unit length " + num(st.rhoI) + " for " + r.elemName(ei));
    const ElementTypeInfo& type = *m.elements[ei].type;
    if (isSpatial(type.slots.front())) {
      if (st.values.size() > type.inertia.size() + type.ignoredInertia.size() || st.values.empty())
        R::fail(st.line,
                r.elemName(ei) + " takes " +
                    (type.inertia.empty() ? std::string("no mass parameters")
                                          : "1 to " + std::to_string(type.inertia.size()) + " mass parameters") +
                    ", found " + std::to_string(st.values.size()));
      for (double v : st.values)
        if (!std::isfinite(v)) R::fail(st.line, "mass parameter is not finite");
      ignoreExtras("EM", ei, st.values.size(), type.inertia.size(), type.ignoredInertia, st.line);
      const size_t own = std::min(st.values.size(), type.inertia.size());
      // Each value into the field its name in the type's layout says (the registry's inertia list).
      // Jxx, Jyy, Jzz and the warping inertia Jw are non-negative (Jyz, a product, may be negative).
      ElementInertia inertia;
      for (size_t k = 0; k < own; ++k) {
        const std::string& name = type.inertia[k].name;
        if (k > 0 && st.values[k] < 0.0 && name != "Jyz")
          R::fail(st.line,
                  std::string(name == "Jw" ? "negative warping inertia " : "negative mass moment of inertia ") +
                      num(st.values[k]) + " for " + r.elemName(ei));
        double ElementInertia::*field = ElementInertia::field(name);
        if (!field) R::fail(st.line, type.keyword + ": the registry's EM parameter " + name + " has no inertia field");
        inertia.*field = st.values[k];
      }
      m.elements[ei].inertia = inertia;
      m.elements[ei].inertiaParams = st.values;
      continue;
    }
    if (st.values.size() > 2)
      R::fail(st.line,
              r.elemName(ei) + " takes 1 or 2 mass parameters (rhoA, rhoI), found " + std::to_string(st.values.size()));
    m.elements[ei].inertia = {st.rhoA, st.rhoI};
    m.elements[ei].inertiaParams = st.values.empty() ? std::vector<double>{st.rhoA, st.rhoI} : st.values;
  }
}

// XM with a tensor: the rigid-body inertia of a spatial orientation node, carried by its L2MIN1.
void ModelBuilder::Finalizer::nodeInertia() {
  for (const auto& st : in.nodeInertias) {
    const int ni = r.node(st.id, st.line, "the inertia would belong to nothing");
    const Node& n = m.nodes[ni];
    if (n.kind != NodeKind::EulerParameters)
      R::fail(st.line, r.nodeDescription(ni) +
                           ": an inertia tensor (6 values) applies to a spatial "
                           "orientation node");
    if (st.values.size() != 6 && st.values.size() != 1)
      R::fail(st.line, "node " + std::to_string(n.label) +
                           ": expected the inertia tensor Ixx Ixy Ixz Iyy Iyz Izz (or one value I), found " +
                           std::to_string(st.values.size()) + " values");
    for (double v : st.values)
      if (!std::isfinite(v)) R::fail(st.line, "inertia is not finite");
    auto it = normalisationOf.find(ni);
    if (it == normalisationOf.end()) continue;  // all four parameters known: the node does not move
    ElementInertia& J = m.elements[it->second].inertia;
    if (st.values.size() == 1) {
      J.jxx = J.jyy = J.jzz = st.values[0];
      J.jxy = J.jxz = J.jyz = 0.0;
    } else {
      J.jxx = st.values[0], J.jxy = st.values[1], J.jxz = st.values[2];
      J.jyy = st.values[3], J.jyz = st.values[4], J.jzz = st.values[5];
    }
    if (J.jxx < 0.0 || J.jyy < 0.0 || J.jzz < 0.0)
      R::fail(st.line, "negative moment of inertia at node " + std::to_string(n.label));
  }
}

// MASS / XM with one value: lumped masses (isotropic rigid-body inertia on a spatial orientation node).
void ModelBuilder::Finalizer::lumpedMasses() {
  std::map<int, double> massByCoord;
  for (const auto& st : in.masses) {
    const int ni = r.node(st.id, st.line, "the mass would belong to nothing");
    const Node& n = m.nodes[ni];
    if (!(st.value >= 0.0) || !std::isfinite(st.value))
      R::fail(st.line, std::string("negative ") + (isTranslational(n.kind) ? "mass " : "rotary inertia ") +
                           num(st.value) + " at node " + std::to_string(n.label));
    if (n.kind == NodeKind::EulerParameters) {  // XM n I: isotropic rigid-body inertia
      if (auto it = normalisationOf.find(ni); it != normalisationOf.end()) {
        ElementInertia& J = m.elements[it->second].inertia;
        J.jxx = J.jyy = J.jzz = st.value;
        J.jxy = J.jxz = J.jyz = 0.0;
      }
      continue;
    }
    for (int c = 0; c < n.dim(); ++c) massByCoord[n.firstCoord + c] = st.value;
  }
  for (const auto& [coord, value] : massByCoord)
    if (value != 0.0) m.lumpedMasses.push_back({coord, value});
}

// XF / FORCE (increment false) or DELXF (true) into f; three values on a spatial orientation node are a
// global moment (SPACAR 2017+; four values: forces on lambda0..3), one entry of m.moments per node.
void ModelBuilder::Finalizer::nodalLoads(const std::vector<Impl::VectorStmt>& stmts, Eigen::VectorXd& f, bool increment,
                                         std::map<int, size_t>& momentAt) {
  for (const auto& st : stmts) {
    const int ni = r.node(st.id, st.line, "the load would act on nothing");
    const Node& n = m.nodes[ni];
    if (n.kind == NodeKind::EulerParameters && st.values.size() == 3) {
      // SPACAR 2017+: a moment in global components (four values: forces on lambda0..3).
      for (double v : st.values)
        if (!std::isfinite(v)) R::fail(st.line, "load is not finite");
      auto [it, fresh] = momentAt.try_emplace(ni, m.moments.size());
      if (fresh) m.moments.push_back({ni, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
      const Eigen::Vector3d v(st.values[0], st.values[1], st.values[2]);
      (increment ? m.moments[it->second].increment : m.moments[it->second].value) += v;
      bool fixed = true;
      for (int c = 0; c < n.dim(); ++c) fixed = fixed && m.xRole[n.firstCoord + c] == Role::Fixed;
      if (fixed && v.squaredNorm() > 0.0)
        m.warnings.push_back("line " + std::to_string(st.line) + ": the moment " + (increment ? "(DELXF" : "(XF") +
                             ") on node " + std::to_string(n.label) +
                             " acts on a fixed orientation (FIX): the support takes it and it moves nothing");
      continue;
    }
    if (isSpatial(n.kind) && static_cast<int>(st.values.size()) > n.dim())
      R::fail(st.line, r.nodeDescription(ni) + ": expected at most " + std::to_string(n.dim()) + " load components" +
                           (n.kind == NodeKind::EulerParameters ? " (3: moment Mx My Mz)" : "") + ", found " +
                           std::to_string(st.values.size()));
    if (static_cast<int>(st.values.size()) > n.dim())
      R::fail(st.line, "node " + std::to_string(n.label) +
                           " is an orientation node: expected 1 component (moment), found " +
                           std::to_string(st.values.size()));
    for (size_t c = 0; c < st.values.size(); ++c) {
      if (!std::isfinite(st.values[c])) R::fail(st.line, "load is not finite");
      const int coord = n.firstCoord + static_cast<int>(c);
      f[coord] += st.values[c];
      // Legal (SPACAR takes it into the support's reaction), but it moves nothing: said, not dropped silently.
      if (st.values[c] != 0.0 && m.xRole[coord] == Role::Fixed)
        m.warnings.push_back("line " + std::to_string(st.line) + ": the load " + (increment ? "(DELXF" : "(XF") +
                             ") on node " + std::to_string(n.label) + ", component " + std::to_string(c + 1) +
                             ", acts on a fixed coordinate (FIX): the support takes it and it moves nothing");
    }
  }
}

void ModelBuilder::Finalizer::loads() {
  m.f0 = Eigen::VectorXd::Zero(m.nx);
  m.delf = Eigen::VectorXd::Zero(m.nx);
  std::map<int, size_t> momentAt;
  nodalLoads(in.forces, m.f0, false, momentAt);
  nodalLoads(in.forceIncrements, m.delf, true, momentAt);
  for (const auto& st : in.timeForces) m.timeForces.push_back({r.x(st.id, st.comp, st.line), st.f});
  if (in.gravity) {
    m.gravity[0] = in.gravity->first;
    m.gravity[1] = in.gravity->second;
    m.gravity[2] = in.gravityZ;
    m.hasGravity = true;
  }
}

void ModelBuilder::Finalizer::stresses() {
  m.sigma0 = Eigen::VectorXd::Zero(m.ne);
  // ESIG e s1 [s2 ... sn]: a value per deformation in the element's order, as ESTIFF and EM list
  // theirs, the rest 0; a later line replaces the row. This is SPACAR's reading: its .sbd of
  // oopspa's `ESIG 1 1.000000` on a HINGE holds ESIG(1,:) = [1 0 0 ...] (io/README.md).
  for (const auto& st : in.prestress) {
    const int ei = r.element(st.id, st.line);
    const ElementEntry& el = m.elements[ei];
    const int n = el.type->numDeformations();
    const std::vector<double>& v = st.values;
    const int k = static_cast<int>(v.size());
    if (k == 0) R::fail(st.line, "ESIG of " + r.elemName(ei) + " gives no value");
    for (double x : v)
      if (!std::isfinite(x)) R::fail(st.line, "prestress is not finite");
    std::string given = "ESIG " + std::to_string(st.id);
    for (double x : v) (given += ' ') += num(x);
    std::vector<double> row = v;
    if (k == 2 && n == 1 && v[0] == 1.0) {
      // flexmb's former ESIG e i s (component, then stress), kept where no other reading fits.
      row = {v[1]};
      note(given + " (line " + std::to_string(st.line) +
           "): flexmb's former form ESIG e 1 s, read as the prestress of " + r.elemName(ei) + "'s only deformation (" +
           el.type->deformationNames[0] + "); SPACAR's form is ESIG " + std::to_string(st.id) + " " + num(v[1]));
    } else if (k > n) {
      std::string hint;
      if (k == 2 && n == 1)
        hint = "; for its one deformation write ESIG " + std::to_string(st.id) +
               " s (flexmb's former ESIG e i s is now a value per deformation)";
      else if (k == 2)
        hint =
            "; flexmb's former ESIG e i s is now written as a value per deformation, e.g. ESIG e 0 0 s for "
            "the third";
      R::fail(st.line, r.elementDescription(ei) + ", ESIG gives " + std::to_string(k) +
                           " values (one per deformation, in this order)" + hint);
    } else if (k == 2 && n >= 2 && v[0] >= 1.0 && v[0] <= static_cast<double>(n) && v[0] == std::floor(v[0])) {
      // Also flexmb's former ESIG e i s (7.5 on deformation 3): read SPACAR's way, and said.
      const int comp = static_cast<int>(v[0]);
      std::string former = "ESIG " + std::to_string(st.id);
      for (int j = 1; j < comp; ++j) former += " 0";
      (former += ' ') += num(v[1]);
      m.warnings.push_back("line " + std::to_string(st.line) + ": " + given +
                           " is read as SPACAR reads it, a value per deformation (" + el.type->deformationNames[0] +
                           " " + num(v[0]) + ", " + el.type->deformationNames[1] + " " + num(v[1]) +
                           "); flexmb before read it as " + num(v[1]) + " on deformation " + std::to_string(comp) +
                           " (" + el.type->deformationNames[comp - 1] + "): for that write " + former);
    }
    row.resize(static_cast<size_t>(n), 0.0);
    for (int j = 0; j < n; ++j) m.sigma0[el.firstDef + j] = row[static_cast<size_t>(j)];
  }
  for (const auto& st : in.timeStresses) m.timeStresses.push_back({r.e(st.id, st.comp, st.line), st.f});
  std::map<int, int> referenceLine;
  for (const auto& st : in.references) {
    const int di = r.e(st.id, st.comp, st.line);
    const ElementEntry& el = m.elements[m.eOwnerElement[di]];
    if (!el.hasStiffness) R::fail(st.line, m.deformationName(di) + " has no stiffness (ESTIFF): a reference needs one");
    if (m.eRole[di] != Role::Dynamic && m.eRole[di] != Role::Calculable)
      R::fail(st.line, m.deformationName(di) + " is " + roleName(m.eRole[di]) +
                           ": a reference applies to a dynamic (DYNE) or released (RLSE) deformation");
    if (auto it = referenceLine.find(di); it != referenceLine.end())
      R::fail(st.line,
              "a reference for " + m.deformationName(di) + " was already given at line " + std::to_string(it->second));
    referenceLine[di] = st.line;
    m.references.push_back({di, st.f});
  }
}

void ModelBuilder::Finalizer::rheonomicInputs() {
  for (int xi : inputXOrder) {
    inputXAt[xi] = m.inputX.size();
    Rheonomic rh;
    rh.index = xi;
    rh.x0 = rh.base = m.x0[xi];
    rh.tRef = m.settings.t0;
    m.inputX.push_back(rh);
  }
  for (int di : inputEOrder) {
    inputEAt[di] = m.inputE.size();
    Rheonomic rh;
    rh.index = di;
    rh.tRef = m.settings.t0;
    m.inputE.push_back(rh);
  }
  for (const auto& st : in.inputXValues) setValues(inputX(st.id, st.comp, st.line), st);
  for (const auto& st : in.inputEValues) setValues(inputE(st.id, st.comp, st.line), st);
  for (const auto& st : in.inputXFunctions) {
    Rheonomic& rh = inputX(st.id, st.comp, st.line);
    rh.fx = st.x, rh.fv = st.v, rh.fa = st.a;
  }
  for (const auto& st : in.inputEFunctions) {
    Rheonomic& rh = inputE(st.id, st.comp, st.line);
    rh.fx = st.x, rh.fv = st.v, rh.fa = st.a;
  }
  for (const auto& st : in.inputIncrements) inputX(st.id, st.comp, st.line).delta = st.value;
  m.xd0 = Eigen::VectorXd::Constant(m.nx, std::numeric_limits<double>::quiet_NaN());
  for (const auto& st : in.coordinateRates) {
    const int xi = r.x(st.id, st.comp, st.line);
    if (m.xRole[xi] == Role::Dynamic) {
      m.xd0[xi] = st.value;
    } else if (m.xRole[xi] == Role::Input) {
      inputX(st.id, st.comp, st.line).v = st.value;
    } else {
      R::fail(st.line, m.coordName(xi) + " is not an input coordinate (it is " + roleName(m.xRole[xi]) +
                           "); XD gives the rate of an input (INPUTX) or dynamic (DYNX) coordinate");
    }
  }
  for (const auto& st : in.coordinateAccelerations) {
    const int xi = r.x(st.id, st.comp, st.line);
    if (m.xRole[xi] == Role::Input) {
      inputX(st.id, st.comp, st.line).a = st.value;
    } else if (m.xRole[xi] != Role::Dynamic) {
      R::fail(st.line, m.coordName(xi) + " is not an input coordinate (it is " + roleName(m.xRole[xi]) +
                           "); XDD gives the acceleration of an input (INPUTX) or dynamic (DYNX) coordinate");
    }
  }
}

Rheonomic& ModelBuilder::Finalizer::inputX(int node, int comp, int line) {
  const int xi = r.x(node, comp, line);
  auto it = inputXAt.find(xi);
  if (it == inputXAt.end())
    R::fail(line, m.coordName(xi) + " is not an input coordinate (it is " + roleName(m.xRole[xi]) +
                      "); declare it with INPUTX in the kinematic block");
  return m.inputX[it->second];
}

Rheonomic& ModelBuilder::Finalizer::inputE(int element, int comp, int line) {
  const int di = r.e(element, comp, line);
  auto it = inputEAt.find(di);
  if (it == inputEAt.end())
    R::fail(line, m.deformationName(di) + " is not an input deformation (it is " + roleName(m.eRole[di]) +
                      "); declare it with INPUTE in the kinematic block");
  return m.inputE[it->second];
}

void ModelBuilder::Finalizer::setValues(Rheonomic& rh, const Impl::CompValues& st) {
  if (st.x) rh.x0 = *st.x;
  if (st.v) rh.v = *st.v;
  if (st.a) rh.a = *st.a;
}

void ModelBuilder::Finalizer::initialDeformations() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.e0 = Eigen::VectorXd::Constant(m.ne, nan);
  m.ed0 = Eigen::VectorXd::Constant(m.ne, nan);
  m.edd0 = Eigen::VectorXd::Constant(m.ne, nan);
  for (const auto& st : in.initialDeformations) {
    const int di = r.e(st.id, st.comp, st.line);
    if (m.eRole[di] == Role::Input) {
      setValues(inputE(st.id, st.comp, st.line), st);
    } else if (m.eRole[di] == Role::Dynamic) {
      if (st.x) m.e0[di] = *st.x;
      if (st.v) m.ed0[di] = *st.v;
      if (st.a) m.edd0[di] = *st.a;
    } else if (m.eRole[di] == Role::Calculable && m.restartState) {
      // A restart state: the value of a released deformation only places the reference (above).
    } else {
      const bool nonzero = (st.x && *st.x != 0.0) || (st.v && *st.v != 0.0) || (st.a && *st.a != 0.0);
      if (nonzero)
        R::fail(st.line, m.deformationName(di) + " is " + roleName(m.eRole[di]) +
                             ": initial values apply to dynamic (DYNE) and input (INPUTE) "
                             "deformations");
    }
  }
}

}  // namespace flexmb::core
