#include "io/formats/KeywordTable.hpp"

#include "io/formats/Visualization.hpp"

#include <algorithm>
#include <cctype>
#include <functional>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace flexmb::io {

namespace {

using Kind = ArgSpec::Kind;

ArgSpec node(std::string name = "node", std::string symbol = "n", Kind kind = Kind::Any) {
  return {ArgType::Node, std::move(name), std::move(symbol), Cardinality::One, kind};
}
ArgSpec element() { return {ArgType::Element, "element", "e", Cardinality::One, Kind::Any}; }
ArgSpec component() { return {ArgType::Component, "component", "i", Cardinality::One, Kind::Any}; }
ArgSpec components() { return {ArgType::Component, "component", "i", Cardinality::Many, Kind::Any}; }
ArgSpec real(std::string name, std::string symbol = "", Cardinality card = Cardinality::One) {
  if (symbol.empty()) symbol = name;
  return {ArgType::Real, std::move(name), std::move(symbol), card, Kind::Any};
}
ArgSpec optReal(std::string name, std::string symbol = "") {
  return real(std::move(name), std::move(symbol), Cardinality::Optional);
}
ArgSpec count(std::string name, std::string symbol) {
  return {ArgType::Count, std::move(name), std::move(symbol), Cardinality::One, Kind::Any};
}
ArgSpec integer(std::string name, std::string symbol, Cardinality card = Cardinality::One) {
  return {ArgType::Integer, std::move(name), std::move(symbol), card, Kind::Any};
}
ArgSpec words() { return {ArgType::Word, "value", "v", Cardinality::Many, Kind::Any}; }
ArgSpec expr(std::string name, Cardinality card = Cardinality::One) {
  std::string sym = "\"" + name + "\"";
  return {ArgType::Expression, std::move(name), std::move(sym), card, Kind::Any};
}

std::string upper(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return r;
}

KeywordInfo kw(std::string name, unsigned dialects, BlockKind block, Action action, std::vector<ArgSpec> args,
               std::string meaning) {
  KeywordInfo k;
  k.name = std::move(name);
  k.dialects = dialects;
  k.block = block;
  k.action = action;
  k.args = std::move(args);
  k.meaning = std::move(meaning);
  return k;
}

KeywordInfo unsupported(std::string name, BlockKind block, std::string meaning, std::string note) {
  KeywordInfo k = kw(std::move(name), kBothDialects, block, Action::Unsupported, {}, std::move(meaning));
  k.unsupportedNote = std::move(note);
  return k;
}

KeywordInfo elementKeyword(const core::ElementTypeInfo& type) {
  std::vector<ArgSpec> args{element()};
  int nPos = 0, nOri = 0, nWarp = 0;
  for (core::NodeKind k : type.slots) {
    const bool pos = core::isTranslational(k), warp = k == core::NodeKind::Warping;
    const int idx = pos ? nPos++ : warp ? nWarp++ : nOri++;
    const char letter = static_cast<char>('p' + std::min(idx, 9));
    args.push_back(node(std::string(pos    ? "node "
                                    : warp ? "warping "
                                           : "orientation ") +
                            letter,
                        std::string(pos    ? "p"
                                    : warp ? "w"
                                           : "o") +
                            std::to_string(idx + 1),
                        pos    ? Kind::Position
                        : warp ? Kind::Warping
                               : Kind::Orientation));
  }
  for (const auto& v : type.vector) args.push_back(real(v.name));
  std::string meaning = type.description;
  if (!type.deformationNames.empty()) {
    meaning += ". Deformations:";
    for (size_t i = 0; i < type.deformationNames.size(); ++i)
      meaning += (i ? ", " : " ") + std::to_string(i + 1) + " " + type.deformationNames[i];
    meaning += ".";
  }
  KeywordInfo k = kw(upper(type.keyword), kBothDialects, BlockKind::Kinematic, Action::Element, std::move(args),
                     std::move(meaning));
  k.elementType = &type;
  return k;
}

std::string stiffnessLayouts() {
  std::string s;
  for (const auto& t : core::elementTypes()) {
    if (!s.empty()) s += "; ";
    s += upper(t.keyword);
    for (const auto& p : t.stiffness) s += " " + p.name;
  }
  return s;
}

std::vector<KeywordInfo> buildTable() {
  using B = BlockKind;
  using A = Action;
  std::vector<KeywordInfo> t;

  // Kinematic block: elements (from the registry), coordinates, roles.
  for (const auto& type : core::elementTypes()) t.push_back(elementKeyword(type));
  t.push_back(kw("X", kBothDialects, B::Kinematic, A::Coordinates,
                 {node(), real("c1"), optReal("c2"), optReal("c3"), optReal("c4")},
                 "initial coordinates of a node: x y of a position node, the angle (rad) of an "
                 "orientation node (default 0); spatial: x y z, or the Euler parameters "
                 "lambda0..lambda3 of an orientation node (default 1 0 0 0), or the rate of twist of "
                 "a BEAMW warping node (default 0)"));
  t.push_back(kw("XYZ", kBothDialects, B::Kinematic, A::Coordinates,
                 {node("node", "n", Kind::Position), real("x"), real("y"), real("z")},
                 "initial coordinates x y z of a spatial position node"));
  t.push_back(kw("LAMBDA", kBothDialects, B::Kinematic, A::Coordinates,
                 {node("node", "o", Kind::Orientation), real("lambda0", "l0"), real("lambda1", "l1"),
                  real("lambda2", "l2"), real("lambda3", "l3")},
                 "initial Euler parameters of a spatial orientation node (default 1 0 0 0)"));
  t.push_back(kw("XY", kBothDialects, B::Kinematic, A::CoordinatesXY,
                 {node("node", "n", Kind::Position), real("x"), real("y")},
                 "initial coordinates x y of a position node"));
  t.push_back(kw("BETA", kBothDialects, B::Kinematic, A::CoordinatesBeta,
                 {node("node", "o", Kind::Orientation), real("angle", "b")},
                 "initial angle (rad) of an orientation node"));
  t.push_back(kw("FIX", kBothDialects, B::Kinematic, A::Fix, {node(), components()},
                 "node coordinates fixed (all of the node without components); on a BEAMW warping "
                 "node: warping restrained (a clamp, a rigid body), otherwise a free warping "
                 "coordinate is a degree of freedom"));
  t.push_back(kw("INPUTX", kBothDialects, B::Kinematic, A::InputXRole, {node(), components()},
                 "node coordinates prescribed in time (rheonomic input)"));
  t.push_back(kw("DYNX", kBothDialects, B::Kinematic, A::DynX, {node(), components()},
                 "node coordinates that are degrees of freedom"));
  t.push_back(kw("DYNE", kBothDialects, B::Kinematic, A::DynE, {element(), components()},
                 "element deformations that are degrees of freedom (elastic, independent)"));
  t.push_back(kw("RLSE", kBothDialects, B::Kinematic, A::Rlse, {element(), components()},
                 "element deformations released: free and calculable (dependent)"));
  t.push_back(kw("INPUTE", kBothDialects, B::Kinematic, A::InputERole, {element(), components()},
                 "element deformations prescribed in time (actuated joint or length)"));

  // Dynamic / static block.
  const std::vector<ArgSpec> massArgs = {node(),         real("mass", "m"), optReal("Ixy"), optReal("Ixz"),
                                         optReal("Iyy"), optReal("Iyz"),    optReal("Izz")};
  t.push_back(kw("MASS", kSpacar95, B::Dynamic, A::LumpedMass, massArgs,
                 "lumped mass on a position node (x and y); rotary inertia on an orientation node"));
  t.push_back(kw("XM", kSpacar2013, B::Dynamic, A::LumpedMass, massArgs,
                 "lumped mass on a position node (x and y; spatial x y z); rotary inertia on an "
                 "orientation node; spatial orientation node: Ixx Ixy Ixz Iyy Iyz Izz (body frame)"));
  t.push_back(kw("EMASS", kSpacar95, B::Dynamic, A::ElementInertia, {element(), real("mass per length", "rhoA")},
                 "mass per unit length of an element"));
  t.push_back(kw("EM", kSpacar2013, B::Dynamic, A::ElementInertia,
                 {element(), real("mass per length", "rhoA"),
                  optReal("rotary inertia per length (planar) or Jxx (spatial)", "rhoI|Jxx"), optReal("Jyy"),
                  optReal("Jzz"), optReal("Jyz"), optReal("Jw")},
                 "mass per unit length of an element; planar beams: rhoA rhoI (rhoI: rotary inertia per "
                 "length, rho I of the section); spatial beams: rhoA Jxx Jyy Jzz Jyz (mass moments of inertia "
                 "per length about the local x (torsion), y and z axes and the product Jyz), BEAMW also Jw "
                 "(warping inertia rho Cw); a 6th value on BEAM or values after rhoA on TRUSS (SPACAR Light, "
                 "oopspa) are ignored with a note; a line with the element alone (oopspa writes them for "
                 "elements without the property) sets nothing, with a note"));
  const std::string layouts = stiffnessLayouts();
  t.push_back(kw("ESTIFF", kBothDialects, B::Dynamic, A::Stiffness,
                 {element(), real("parameter", "p", Cardinality::Many)},
                 "stiffness parameters (" + layouts +
                     "); 0 may stand for an unused deformation. BEAM/BEAMNL cy cz: shear flexibility of "
                     "bending about the local y and z axes, EIy/(k G A) and EIz/(k G A) (m^2, k: shear "
                     "correction factor; Timoshenko, Phi = 12 c / l0^2; 0 or absent: Euler-Bernoulli, no "
                     "shear deformation); the values after an element's own layout that SPACAR Light and "
                     "oopspa write (BEAMW's seven for every BEAM and TRUSS) are ignored with a note; BEAMW "
                     "needs all seven; a line with the element alone (oopspa writes them for elements without "
                     "the property) sets nothing, with a note"));
  t.push_back(kw("EDAMPP", kSpacar95, B::Dynamic, A::Damping, {element(), real("parameter", "p", Cardinality::Many)},
                 "damping coefficients, same layout as ESTIFF"));
  t.push_back(kw("EDAMP", kSpacar2013, B::Dynamic, A::Damping, {element(), real("parameter", "p", Cardinality::Many)},
                 "damping coefficients, same layout as ESTIFF; a line with the element alone (oopspa writes "
                 "them for elements without the property) sets nothing, with a note"));
  const std::vector<ArgSpec> loadArgs = {node(), real("f1"), optReal("f2"), optReal("f3"), optReal("f4")};
  t.push_back(kw("FORCE", kSpacar95, B::Dynamic, A::Force, loadArgs,
                 "constant nodal force Fx Fy (position node) or moment (orientation node); spatial: "
                 "Fx Fy Fz, or four forces on the Euler parameters"));
  t.push_back(kw("XF", kSpacar2013, B::Dynamic, A::Force, loadArgs,
                 "constant nodal force Fx Fy (position node) or moment (orientation node); spatial: "
                 "Fx Fy Fz, on an orientation node the global moment Mx My Mz (four values: forces "
                 "on the Euler parameters, older SPACAR)"));
  t.push_back(kw("DELXF", kSpacar2013, B::Dynamic, A::ForceIncrement, loadArgs,
                 "load increment of a static analysis: the TOTAL increment reached at the last load "
                 "step, applied in equal parts; on a spatial orientation node the global moment"));
  t.push_back(kw("GRAVITY", kSpacar2013, B::Dynamic, A::Gravity, {real("gx"), real("gy"), optReal("gz")},
                 "gravitational acceleration (planar models: gz, out of the plane, has no effect)"));
  t.push_back(kw("XD", kSpacar95, B::Dynamic, A::XD, {node(), component(), real("rate", "v")},
                 "rate of an input coordinate at the current time, x(t) = x + v (t - TIME) + a (t - TIME)^2/2 "
                 "(X gives x); on a DYNX coordinate its initial rate"));
  t.push_back(kw("XDD", kSpacar95, B::Dynamic, A::XDD, {node(), component(), real("acceleration", "a")},
                 "acceleration of an input coordinate: x(t) = x + v (t - TIME) + a (t - TIME)^2/2; on a DYNX "
                 "coordinate (an echoed end state) accepted and not used: the equations of motion give it"));
  t.push_back(kw("INPUTX", kBothDialects, B::Dynamic, A::InputXValues,
                 {node(), component(), real("x"), optReal("v"), optReal("a")},
                 "value, rate, acceleration of an input coordinate: x(t) = x + v t + a t^2/2 "
                 "(x defaults to the initial coordinate)"));
  t.push_back(kw("INPUTE", kBothDialects, B::Dynamic, A::InputEValues,
                 {element(), component(), real("value", "x"), optReal("v"), optReal("a")},
                 "value, rate, acceleration of an input deformation: e(t) = e + v t + a t^2/2 "
                 "(flexmb: by analogy with INPUTX)"));
  t.push_back(kw("E", kSpacar95, B::Dynamic, A::E, {element(), component(), real("value", "v")},
                 "initial value of a deformation (the value at t = 0 of an input deformation)"));
  t.push_back(kw("ED", kSpacar95, B::Dynamic, A::ED, {element(), component(), real("rate", "v")},
                 "initial rate of a deformation (the rate of an input deformation)"));
  t.push_back(kw("EDD", kSpacar95, B::Dynamic, A::EDD, {element(), component(), real("acceleration", "v")},
                 "acceleration of an input deformation; on a dynamic one (an echoed end state) accepted and not "
                 "used: the equations of motion give it"));
  t.push_back(kw("STARTDE", kSpacar2013, B::Dynamic, A::StartDE, {element(), component(), real("e0"), optReal("ed0")},
                 "initial value and rate of a deformation"));
  t.push_back(kw("DELINPX", kSpacar2013, B::Dynamic, A::InputIncrement, {node(), component(), real("increment", "dx")},
                 "increment of an input coordinate in a static analysis: the TOTAL increment reached "
                 "at the last load step, applied in equal parts"));
  t.push_back(kw("ESIG", kSpacar2013, B::Dynamic, A::Prestress,
                 {element(), real("stress", "s1"), real("stress", "s2", Cardinality::Many)},
                 "prestress (generalized stress at zero deformation) of the element's deformations, one value "
                 "per deformation in the element's deformation order, as ESTIFF and EM list theirs: ESIG e s1 "
                 "[s2 ... sn]; values left off at the end are 0, a later ESIG for the element replaces them "
                 "(SPACAR reads oopspa's ESIG 1 1.0 on a HINGE as the pre-torque of its rotation). flexmb's "
                 "former ESIG e 1 s on an element with one deformation is read with a note; two values on an "
                 "element with more deformations, the first a deformation number (ESIG 2 3 7.5), are read "
                 "SPACAR's way with a warning (the former reading, 7.5 on deformation 3, is ESIG 2 0 0 7.5); a "
                 "line with the element alone (oopspa writes them for elements without the property) sets "
                 "nothing, with a note"));
  {
    KeywordInfo ts = kw("TIMESTEP", kBothDialects, B::Dynamic, A::TimeStep,
                        {real("end time", "T"), count("number of output intervals", "n")},
                        "SPACAR 2013+: end time T and n output intervals; SPACAR95 (TIMESTEP n Tp): n output "
                        "intervals over a period Tp from the current time (TIME, or the end of the previous run)");
    ts.args95 = {count("number of output intervals", "n"), real("end time", "T")};
    t.push_back(std::move(ts));
  }
  t.push_back(kw("EPSINT", kSpacar95, B::Dynamic, A::EpsInt, {real("tolerance", "eps")},
                 "integrator tolerance: flexmb uses it as both relative and absolute tolerance"));
  t.push_back(kw("ERROR", kSpacar2013, B::Dynamic, A::ErrorTol,
                 {real("absolute tolerance", "atol"), real("relative tolerance", "rtol")},
                 "integrator tolerances (defaults 1e-6 and 1e-3, as ode45)"));
  t.push_back(kw("HMAX", kSpacar95, B::Dynamic, A::HMax, {real("maximum step", "h")}, "maximum integrator step size"));
  t.push_back(kw("EPSKIN", kSpacar95, B::Dynamic, A::EpsKin, {real("tolerance", "eps")},
                 "tolerance of the kinematic Newton iteration"));
  t.push_back(kw("MAXITERAT", kSpacar95, B::Dynamic, A::MaxIterat, {count("maximum iterations", "n")},
                 "iteration limit of the kinematic Newton iteration"));
  t.push_back(kw("ITERSTEP", kSpacar2013, B::Dynamic, A::IterStep,
                 {count("maximum iterations", "maxit"), count("number of load steps", "nsteps"),
                  optReal("tolerance", "tol"), integer("control field 4 (unused)", "c4", Cardinality::Optional),
                  integer("control field 5 (unused)", "c5", Cardinality::Optional),
                  integer("number of initial-load steps", "ninit", Cardinality::Optional)},
                 "Newton iteration limit; number of load steps over which the DEL* increments are "
                 "applied (in equal parts, the total reached at the last step); Newton tolerance; two "
                 "control fields flexmb reads but does not use; number of steps over which the "
                 "initial loads (XF, INPUTX values, gravity) are applied first (0 or absent: at once). SPACAR "
                 "Light writes e.g. ITERSTEP 10 9 0.0000005 1 3 9"));
  t.push_back(kw("TIME", kBothDialects, B::Anywhere, A::Time, {real("start time", "t0")},
                 "current (start) time; SPACAR95 TIMESTEP integrates from it, input coordinates move "
                 "as x + v (t - TIME) + a (t - TIME)^2/2 (in SPACAR 2013+ files a flexmb extension, "
                 "written by restart echoes)"));
  t.push_back(kw("OUTLEVEL", kSpacar2013, B::Anywhere, A::OutLevel,
                 {integer("output level", "a"), integer("transfer functions", "b", Cardinality::Optional)},
                 "output level; b = 1 asks for the first-order transfer functions (dx) in the results"));
  t.push_back(kw("LENGTH0", kBothDialects, B::Anywhere, A::Length0, {element(), real("reference length", "l0")},
                 "reference (undeformed) length of an element, as SPACAR95 prints it in its end-of-run "
                 "state: the element's coordinates X are then its current configuration and its "
                 "deformations there are E (0 where not given), so a restart keeps the undeformed "
                 "geometry"));
  for (const char* name : {"LGEOMY", "DIR", "EPSIND", "FORCEMODE", "ANIMATE", "MATASC", "RESTART", "JOBID"})
    t.push_back(kw(name, kBothDialects, B::Anywhere, A::Ignored, {words()},
                   "SPACAR95 run setting written in its end-of-run state; accepted and ignored "
                   "(listed once as ignored by check and the analyses)"));

  // flexmb extensions (section 6).
  auto ext = [](KeywordInfo k) {
    k.extension = true;
    return k;
  };
  t.push_back(ext(kw("XFT", kBothDialects, B::Dynamic, A::TimeForce, {node(), component(), expr("f(t)")},
                     "time-dependent nodal force component, added to XF/FORCE")));
  t.push_back(ext(kw("ESIGT", kBothDialects, B::Dynamic, A::TimeStress, {element(), component(), expr("sigma(t)")},
                     "time-dependent generalized stress (actuator force or torque) added to sigma; per "
                     "component (ESIGT e i), unlike ESIG, which lists a value per deformation")));
  t.push_back(ext(kw("EREF", kBothDialects, B::Dynamic, A::Reference, {element(), component(), expr("eref(t)")},
                     "time-dependent rest value of a deformation: sigma = S (e - eref(t))")));
  t.push_back(ext(kw("INPUTXT", kBothDialects, B::Dynamic, A::InputXFunctions,
                     {node(), component(), expr("x(t)"), expr("v(t)"), expr("a(t)")},
                     "prescribed input coordinate with its rate and acceleration")));
  t.push_back(ext(kw("INPUTET", kBothDialects, B::Dynamic, A::InputEFunctions,
                     {element(), component(), expr("e(t)"), expr("v(t)"), expr("a(t)")},
                     "prescribed input deformation with its rate and acceleration")));
  t.push_back(ext(kw("XREF", kBothDialects, B::Kinematic, A::ReferenceCoordinates,
                     {node(), real("c1"), optReal("c2"), optReal("c3"), optReal("c4")},
                     "reference coordinates of a node, as X lists them: the configuration its elements "
                     "are created in (undeformed), where X gives another (the current one). Written by "
                     "the restart echo of a spatial model (simulate --echo) for every node that moved: "
                     "X and XREF then hold the end of the run and the original geometry, the element "
                     "lines their original y vectors; SPACAR has no public keyword for it")));

  // Block structure.
  t.push_back(kw("END", kBothDialects, B::Structure, A::End, {},
                 "closes a block; END directly after END (an empty block) ends the input"));
  t.push_back(kw("HALT", kBothDialects, B::Structure, A::Halt, {},
                 "after the kinematic block's END: separator (SPACAR 2013+ END HALT); after a later "
                 "block's END: ends the input"));
  t.push_back(kw("EOF", kBothDialects, B::Structure, A::Eof, {},
                 "after a block's END: ends the input; the rest of the file is ignored"));
  t.push_back(
      kw("VISUALIZATION", kBothDialects, B::Structure, A::Visualization, {},
         "after a block's END (SPACAR Light: after END END, where it is found too): the visualization section, to the "
         "end of the file: drawing hints "
         "for the pictures (cross-sections, colours, hidden elements; see the VISUALIZATION "
         "section below), never used by the analyses"));

  // SPACAR keywords flexmb does not support (yet).
  // The element types of one kind (planar or spatial), for "use one of these instead".
  auto typesOfKind = [](bool spatialKind) {
    std::string s;
    for (const auto& ty : core::elementTypes())
      if (!ty.slots.empty() && core::isSpatial(ty.slots.front()) == spatialKind)
        s += (s.empty() ? "" : ", ") + upper(ty.keyword);
    return s;
  };
  const std::string spatial = "not implemented in flexmb; spatial elements: " + typesOfKind(true);
  const std::string planarNote = "not implemented in flexmb; planar elements: " + typesOfKind(false);
  // Spatial SPACAR keywords: the `spatial` work registers element types under these names; an
  // entry is dropped here as soon as an element type of that name exists, so it needs no edit.
  const std::pair<const char*, const char*> spatialKeywords[] = {
      {"BEAM", "spatial beam element"},
      {"BEAMNL", "spatial beam element with the nonlinear (second-order) elongation terms"},
      {"BEAMW", "spatial beam element with warping"},
      {"RBEAM", "spatial beam element variant (RBEAM)"},
      {"TRUSS", "spatial truss element"},
      {"HINGE", "spatial hinge element"},
      {"PINBAR", "spatial pinned bar element"},
      {"BEARING", "spatial bearing element"},
      {"SURFACE", "spatial surface (contact) element"},
      {"PINBODY", "spatial pin-body element"},
      {"TUBE", "spatial tube (sliding) element"},
      {"SCREW", "spatial screw element"},
      {"LAMBDA", "constraint on the Euler parameters of a spatial orientation node"},
      {"L2MIN1", "Euler-parameter normalisation constraint (lambda^2 - 1 = 0) of a spatial orientation node"},
      {"XYZ", "spatial node coordinates"},
  };
  auto known = [&t](const char* name) {
    return std::any_of(t.begin(), t.end(), [&](const KeywordInfo& k) { return k.name == name; });
  };
  t.push_back(unsupported("L2MIN1", B::Kinematic, "Euler-parameter normalisation element",
                          "flexmb creates it for every orientation node: leave it out"));
  for (const auto& [name, meaning] : spatialKeywords)
    if (!known(name)) t.push_back(unsupported(name, B::Kinematic, meaning, spatial));
  const std::pair<const char*, const char*> planarKeywords[] = {
      {"PLBELT", "planar belt element"},
      {"PLBEAR", "planar bearing element"},
      {"PLWHEEL", "planar wheel (rolling contact) element"},
      {"PLTUBE", "planar tube (sliding) element"},
      {"PLPINBODY", "planar pin-body element"},
  };
  for (const auto& [name, meaning] : planarKeywords)
    if (!known(name)) t.push_back(unsupported(name, B::Kinematic, meaning, planarNote));
  const std::string control = "flexmb does not build control-system models yet";
  t.push_back(unsupported("NOMS", B::Dynamic, "control-system keyword of SPACAR (NOMS)", control));
  t.push_back(unsupported("NOMF", B::Dynamic, "control-system keyword of SPACAR (NOMF)", control));
  t.push_back(unsupported("REFES", B::Dynamic, "control-system reference keyword of SPACAR (REFES)", control));
  t.push_back(unsupported("REFEF", B::Dynamic, "control-system reference keyword of SPACAR (REFEF)", control));
  t.push_back(unsupported("LINE", B::Dynamic, "SPACAR keyword LINE", "not implemented in flexmb"));
  t.push_back(unsupported("ENHC", B::Dynamic, "SPACAR keyword ENHC", "not implemented in flexmb"));
  // Mode 9 (SPACAR Light's transfer option): the transfer block after a second END HALT.
  auto transfer = [&](const char* name, const char* meaning) {
    KeywordInfo k =
        kw(name, kSpacar2013, B::Transfer, A::Transfer, {count("channel number", "k"), node(), component()}, meaning);
    k.transfer = true;
    t.push_back(std::move(k));
  };
  transfer("INPUTF",
           "input k of the transfer function: a force on coordinate i of node n (a calculable or DYNX "
           "coordinate); on a spatial orientation node a moment about the global axis i = 1, 2, 3");
  transfer("INX",
           "input k of the transfer function: the prescribed motion of coordinate i of node n (an INPUTX "
           "coordinate of the kinematic block); gives three input channels, its position, velocity and "
           "acceleration");
  transfer("OUTX",
           "output k: coordinate i of node n (on a spatial orientation node the rotation about the global "
           "axis i = 1, 2, 3)");
  transfer("OUTXP", "output k: the velocity of coordinate i of node n (spatial orientation node: angular velocity)");
  transfer("OUTF",
           "output k: the force a fixed or input coordinate i of node n takes (fxt: the support reaction; "
           "on a spatial orientation node the moment about the global axis i)");
  // MATLAB user functions: read here, run by the Octave/MATLAB gateway spacar() (tools/octave);
  // the command line stops with a message saying so.
  const ArgSpec fname{ArgType::Name, "MATLAB function name", "fname", Cardinality::One, ArgSpec::Kind::Any};
  t.push_back(kw("USERINP", kBothDialects, B::Dynamic, A::UserInput, {fname},
                 "MATLAB function [t, e, x] = fname(t, is) giving the input coordinates and deformations "
                 "(is = 0, 1, 2: values, rates, accelerations); runs through spacar() in Octave/MATLAB"));
  t.push_back(kw("USERSIG", kBothDialects, B::Dynamic, A::UserStress, {fname},
                 "MATLAB function [time, sig, f] = fname(t, ne, le, e, ep, nx, lnp, x, xp) adding stresses and "
                 "nodal forces [node component value]; runs through spacar() in Octave/MATLAB"));
  return t;
}

const char* dialectText(unsigned d) {
  switch (d) {
    case kSpacar95:
      return "95";
    case kSpacar2013:
      return "13";
    default:
      return "95 13";
  }
}

bool allOf(const std::vector<ArgSpec>& layout, ArgType a, ArgType b = ArgType::Expression,
           ArgType c = ArgType::Expression, ArgType d = ArgType::Expression) {
  return std::all_of(layout.begin(), layout.end(),
                     [&](const ArgSpec& s) { return s.type == a || s.type == b || s.type == c || s.type == d; });
}

}  // namespace

const std::vector<ArgSpec>& KeywordInfo::layout(bool spacar95) const {
  return spacar95 && !args95.empty() ? args95 : args;
}

int KeywordInfo::minArgs(const std::vector<ArgSpec>& layout) {
  return static_cast<int>(
      std::count_if(layout.begin(), layout.end(), [](const ArgSpec& s) { return s.card == Cardinality::One; }));
}

int KeywordInfo::maxArgs(const std::vector<ArgSpec>& layout) {
  for (const auto& s : layout)
    if (s.card == Cardinality::Many) return -1;
  return static_cast<int>(layout.size());
}

std::string KeywordInfo::expectation(const std::vector<ArgSpec>& layout) {
  const int lo = minArgs(layout), hi = maxArgs(layout);
  if (layout.empty()) return "expected no arguments";
  std::string noun;
  if (allOf(layout, ArgType::Node, ArgType::Element, ArgType::Component, ArgType::Count))
    noun = "integer";
  else if (std::any_of(layout.begin(), layout.end(),
                       [](const ArgSpec& s) { return s.type == ArgType::Expression || s.type == ArgType::Name; }))
    noun = "argument";
  else
    noun = "number";
  std::ostringstream o;
  o << "expected ";
  if (hi < 0)
    o << "at least " << lo << " " << noun << (lo == 1 ? "" : "s");
  else if (hi == lo)
    o << lo << " " << noun << (lo == 1 ? "" : "s");
  else
    o << lo << " to " << hi << " " << noun << "s";
  o << " (";
  for (size_t i = 0; i < layout.size(); ++i) {
    const ArgSpec& s = layout[i];
    if (i) o << ", ";
    const std::string nm = s.type == ArgType::Expression ? "\"" + s.name + "\"" : s.name;
    if (s.card == Cardinality::One)
      o << nm;
    else if (s.card == Cardinality::Optional)
      o << "[" << nm << "]";
    else
      o << "[" << nm << " ...]";
  }
  o << ")";
  return o.str();
}

std::string KeywordInfo::synopsis(const std::string& name, const std::vector<ArgSpec>& layout) {
  std::string s = name;
  int openOptional = 0;
  for (const auto& a : layout) {
    if (a.card == Cardinality::One) {
      s += " " + a.symbol;
    } else if (a.card == Cardinality::Optional) {
      s += " [" + a.symbol;
      ++openOptional;
    } else {
      s += " [" + a.symbol + " ...]";
    }
  }
  s += std::string(openOptional, ']');
  return s;
}

const std::vector<KeywordInfo>& keywordTable() {
  static const std::vector<KeywordInfo> table = buildTable();
  return table;
}

std::vector<const KeywordInfo*> findKeywords(std::string_view name) {
  const std::string u = upper(name);
  std::vector<const KeywordInfo*> r;
  for (const auto& k : keywordTable())
    if (k.name == u) r.push_back(&k);
  return r;
}

const KeywordInfo* findKeyword(std::string_view name, BlockKind block) {
  for (const KeywordInfo* k : findKeywords(name))
    if (k->block == block || k->block == BlockKind::Anywhere) return k;
  return nullptr;
}

int editDistance(std::string_view a, std::string_view b) {
  const size_t n = a.size(), m = b.size();
  std::vector<int> prev(m + 1), cur(m + 1);
  for (size_t j = 0; j <= m; ++j) prev[j] = static_cast<int>(j);
  for (size_t i = 1; i <= n; ++i) {
    cur[0] = static_cast<int>(i);
    for (size_t j = 1; j <= m; ++j) {
      const bool same =
          std::toupper(static_cast<unsigned char>(a[i - 1])) == std::toupper(static_cast<unsigned char>(b[j - 1]));
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (same ? 0 : 1)});
    }
    std::swap(prev, cur);
  }
  return prev[m];
}

std::string suggestKeyword(std::string_view unknown) {
  if (unknown.empty() || unknown.size() > 64) return "";
  std::string best;
  int bestD = 1 << 30;
  for (const auto& k : keywordTable()) {
    const int d = editDistance(unknown, k.name);
    if (d < bestD) {
      bestD = d;
      best = k.name;
    }
  }
  // Close enough to be a plausible typo: at most a third of the longer word (and at least 1).
  const int limit = std::max<int>(1, static_cast<int>(std::max(unknown.size(), best.size())) / 3);
  return bestD <= limit ? best : "";
}

namespace {

struct Group {
  const char* title;
  std::function<bool(const KeywordInfo&)> pick;
};

const std::vector<Group>& groups() {
  static const std::vector<Group> g = {
      {"Kinematic block (the first block: elements, coordinates, roles)",
       [](const KeywordInfo& k) {
         return k.block == BlockKind::Kinematic && k.action != Action::Unsupported && !k.extension;
       }},
      {"Dynamic / static block (after the kinematic block's END; in SPACAR95 also the first block)",
       [](const KeywordInfo& k) {
         return k.block == BlockKind::Dynamic && k.action != Action::Unsupported && !k.extension;
       }},
      {"Any block (settings; SPACAR95 end-of-run state)",
       [](const KeywordInfo& k) { return k.block == BlockKind::Anywhere; }},
      {"flexmb extensions: time functions (muParser expressions in t, in double quotes) and the spatial "
       "restart's reference coordinates",
       [](const KeywordInfo& k) { return k.extension; }},
      {"Mode-9 transfer block (between a second END HALT and the final END END; `flexmb transfer`, "
       "`spacar(9, name)`)",
       [](const KeywordInfo& k) { return k.block == BlockKind::Transfer; }},
      {"Block structure", [](const KeywordInfo& k) { return k.block == BlockKind::Structure; }},
      {"SPACAR keywords recognised but not supported by flexmb yet",
       [](const KeywordInfo& k) { return k.action == Action::Unsupported; }},
  };
  return g;
}

std::string status(const KeywordInfo& k) {
  if (k.action == Action::Unsupported) return "not supported yet";
  if (k.action == Action::Ignored) return "accepted, ignored";
  if (k.extension) return "flexmb extension";
  return "supported";
}

std::string dialectWords(unsigned d) {
  switch (d) {
    case kSpacar95:
      return "SPACAR95";
    case kSpacar2013:
      return "SPACAR 2013+";
    default:
      return "both";
  }
}

std::string cell(std::string s) {
  std::string r;
  for (char c : s) r += c == '|' ? std::string("\\|") : std::string(1, c);
  return r;
}

}  // namespace

void printKeywords(std::ostream& out) {
  const auto& table = keywordTable();
  out << "Keywords of the .dat language read by flexmb. Full reference (both dialects, block structure,\n"
         "load steps, restarts): io/dat-language.md in the source tree (flexmb keywords --markdown).\n"
         "Dialects: 95 = SPACAR95 only, 13 = SPACAR 2013+ only, '95 13' = both; 'ext' = flexmb "
         "extension.\n"
         "Keywords are case-insensitive. Comments: '*' in column 1, or '%', '#', ';' to the end "
         "of the line.\n";
  auto line = [&](const std::string& syn, const std::string& dia, const std::string& meaning) {
    out << "  " << std::left << std::setw(34) << syn << " " << std::setw(6) << dia << " " << meaning << "\n";
  };
  for (const auto& g : groups()) {
    out << "\n" << g.title << "\n";
    for (const auto& k : table) {
      if (!g.pick(k)) continue;
      if (k.action == Action::Unsupported) {
        line(k.name, "", k.meaning + ": " + k.unsupportedNote);
        continue;
      }
      const std::string dia = k.extension ? "ext" : dialectText(k.dialects);
      if (!k.args95.empty()) {
        line(KeywordInfo::synopsis(k.name, k.args), "13", k.meaning);
        line(KeywordInfo::synopsis(k.name, k.args95), "95", "(SPACAR95 field order)");
      } else {
        line(KeywordInfo::synopsis(k.name, k.args), dia, k.meaning);
      }
    }
  }
}

void printKeywordsMarkdown(std::ostream& out) {
  out << R"(<!-- Generated by `flexmb keywords --markdown` from io/formats/KeywordTable.cpp: do not edit by hand.
     io_tests (KeywordTable.MarkdownReferenceIsCurrent) fails when this file differs from the table. -->
# The `.dat` language flexmb reads

flexmb reads SPACAR model files unchanged, in both dialects: **SPACAR95** (TU Delft, Fortran) and
**SPACAR 2013+** (U. Twente, called from MATLAB as `spacar(mode, name)`; also what SPACAR Light
writes). The dialect is decided per file from the keywords it uses (a keyword marked "SPACAR95" or
"SPACAR 2013+" below is one dialect's only; `--dialect 95|2013` overrides it); a file mixing both
is an error naming one keyword of each.

## Lexical rules
- One keyword per line, then its fields separated by blanks or tabs. Keywords are case-insensitive.
- Comments: `*` in column 1 (SPACAR95); `%`, `#` or `;` to the end of the line. Blank lines are ignored.
- Numbers: integers, reals with `.` as the decimal separator and `E` or Fortran `D` exponents. An
  integer field may be written as a whole number with decimals (`1000.000000`); a non-whole value
  (`2.5`) is an error. A comma is not a separator: a decimal comma (`-9,81`) is an error that says so.
- Node and element numbers are user-chosen positive integers. A node's kind (position,
  orientation or, for `BEAMW`, warping) is fixed by the element slot that first uses it.

## Blocks and analyses
- **SPACAR 2013+**: the kinematic block, `END` `HALT`, the dynamic/static block, `END` `END`. Mode 9
  writes a transfer block between a second `END HALT` and the final `END END` (`INPUTF`, `INX`,
  `OUTX`, `OUTXP`, `OUTF`, each `keyword k n i`: channel number k, node n, component i; the numbers
  of the inputs and of the outputs each run 1, 2, ... without gaps): `flexmb transfer` and
  `spacar(9, name)` compute the state-space model at the last load step from it; other analyses
  ignore it. Names the reader refuses, with the line: a node that does not exist, a component the
  node does not have, a fixed coordinate as input or OUTX/OUTXP output, a force input on an input
  (INPUTX) coordinate (not a load point: the prescribed motion takes it), INX on a coordinate that
  is not an input coordinate, OUTF on a calculable or DYNX coordinate (the force there is the
  applied load). A `VISUALIZATION` section after the final `END` gives drawing hints (see the
  section below).
- **SPACAR95**: a sequence of blocks, each closed by `END`, up to `EOF` or the end of the file. The
  first block may hold every keyword at once (elements, coordinates, roles, masses, `TIMESTEP`, ...).
  At each `END` the analysis runs over that block's period; reading then resumes and a later block
  changes data (loads, stiffness, input rates, settings) and continues from the current state. A role
  keyword repeated in a later block (`INPUTX 2 1`, `FIX 1`, `DYNE 3`) restates the role; elements
  and coordinates belong to the first block; initial values (`E`, `ED`) after a block that ran are an
  error (the state carries over).
- **Time (SPACAR95)**: `TIMESTEP n Tp` integrates over a period `Tp` from the current time (`TIME t`,
  default 0; after a block that ran, its end time) in `n` output intervals. An input coordinate given
  by its value (`X`, `XY`, `BETA`) and rate (`XD`, `XDD`) moves as
  x(t) = x + v (t - TIME) + a (t - TIME)^2 / 2. SPACAR 2013+: `TIMESTEP T n`, end time `T`;
  `INPUTX n i x v a` moves as x + v t + a t^2 / 2.
- **Restart**: the end-of-run state (`flexmb simulate --echo file`, as SPACAR95 prints it) is a
  complete input that continues the run: elements, the current `XY`/`BETA`, roles, `LENGTH0` of
  every element, `E`/`ED` of the deformations, input rates `XD`, `TIME`, loads and settings. A file
  with `LENGTH0` is a restart state: its coordinates are the current configuration, the deformations
  there are the given `E` (0 where not given) and reference lengths come from `LENGTH0`, so a
  restart from a deformed state keeps the undeformed geometry. SPACAR95 run settings without meaning
  in flexmb (`LGEOMY`, `DIR`, `EPSIND`, `FORCEMODE`, `ANIMATE`, `MATASC`, `RESTART`, `JOBID`) are
  accepted and listed once as ignored. A spatial model's end-of-run state (flexmb's; SPACAR
  publishes no spatial restart format) is written in SPACAR 2013+ form: the element lines with their
  original y vectors, `X` of every node where the run ended (positions, Euler parameters), `XREF` (a
  flexmb extension) with the original coordinates of every node that moved, so that the elements read
  back have the reference lengths and triads of the run, roles, `STARTDE` value and rate of every
  `DYNE` deformation, inputs, `TIME`, loads (moments as `XF n Mx My Mz`) and settings. A spatial
  model with a coordinate degree of freedom (`DYNX`, a free BEAMW warping coordinate) is refused: SPACAR
  2013+ has no keyword for its rate.
- **Load steps (static analysis, mode 10)**: `ITERSTEP maxit nsteps tol c4 c5 ninit`. `DELXF` and
  `DELINPX` are the TOTAL increments reached at the last load step, applied in `nsteps` equal parts
  (SPACAR Light writes the user's final load as `DELXF`). Load step 0 is the equilibrium under the
  initial loads (`XF`, the `INPUTX` values and gravity), load step i adds i/nsteps of the increments:
  `nsteps + 1` load steps, stored as the records of the `.sbd` (io/results.md). The initial loads are
  ramped over `ninit` steps before load step 0 (0 or absent: at once, within load step 0); the ramp
  steps are computed and listed in the CSV, not stored in the `.sbd`. Without any `DEL*` increment
  and with `ninit` 0, the initial loads take the increments' place (load step 0 unloaded, load step i
  carries i/nsteps of them), so `XF` with n steps gives n distinct equilibria. Gravity is an initial
  load (ramped with them, so every path starts from the unloaded reference configuration); time
  functions are evaluated at the start time and not ramped. The control fields `c4`, `c5` are read
  and not used.
- **Stiffness**: `DYNE` and `RLSE` deformations of an element with `ESTIFF` carry stress
  sigma = S e (+ damping); fixed deformations carry reaction stresses only.
)";
  out << "\n## Keywords\nStatus: supported; flexmb extension; accepted, ignored; not supported yet (recognised, "
         "reported as a SPACAR keyword flexmb does not support, never as unknown).\n";
  const auto& table = keywordTable();
  for (const auto& g : groups()) {
    out << "\n### " << g.title << "\n\n| keyword | fields | dialect | status | meaning |\n|---|---|---|---|---|\n";
    for (const auto& k : table) {
      if (!g.pick(k)) continue;
      std::string syn = k.action == Action::Unsupported ? k.name : KeywordInfo::synopsis(k.name, k.args);
      std::string dia = k.action == Action::Unsupported ? "" : dialectWords(k.dialects);
      if (!k.args95.empty()) {
        syn = KeywordInfo::synopsis(k.name, k.args) + "`<br>`" + KeywordInfo::synopsis(k.name, k.args95);
        dia = "2013+<br>SPACAR95";
      }
      std::string meaning = k.meaning;
      if (k.action == Action::Unsupported) meaning += "; " + k.unsupportedNote;
      out << "| `" << k.name << "` | `" << cell(syn) << "` | " << dia << " | " << status(k) << " | " << cell(meaning)
          << " |\n";
    }
  }
  out << "\n## VISUALIZATION section\nAfter the final `END` (or after `END END`, where SPACAR Light writes it and "
         "SPACAR reads no "
         "more input), `VISUALIZATION` starts a section of drawing hints, as SPACAR Light and oopspa write it. The "
         "pictures (`flexmb show`, `--svg`, `--html`) draw beams with these "
         "cross-sections (else with the rectangle of the section's radii of gyration from `EM` or `ESTIFF`), and "
         "leave out `DONOTDRAW` elements; the analyses never read it. What the section holds that flexmb cannot "
         "use (an unknown statement, a value out of range, an element the model does not have) is a note, never "
         "an error.\n\n| statement | meaning |\n|---|---|\n";
  for (const auto& [name, meaning] : visualizationKeywords()) out << "| `" << name << "` | " << cell(meaning) << " |\n";
}

}  // namespace flexmb::io
