// Model templates of design studies (io/templates/ModelTemplate.hpp): substitution, definitions and defaults,
// and the error messages (file:line of the template, unknown parameter, bad expression).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "io/formats/DatReader.hpp"
#include "io/templates/ModelTemplate.hpp"

using flexmb::io::ModelTemplate;
using flexmb::io::TemplateError;

namespace {

// The error message of f(), or "" when it does not throw a TemplateError.
template <class F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const TemplateError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ModelTemplate, ReplacesPlaceholdersByRoundTripValues) {
  const ModelTemplate t("ESTIFF 1 {EA} {2*EI}\n% t = {t} m\nX 2 {L} 0.0\n", "a.dat");
  t.check({"EA", "EI", "t", "L"});
  const std::string out = t.instantiate({{"EA", 8.4e6}, {"EI", 1.4}, {"t", 1.5e-4}, {"L", 0.1 + 0.2}});
  EXPECT_EQ(out, "ESTIFF 1 8.4e+06 2.8\n% t = 0.00015 m\nX 2 0.30000000000000004 0.0\n");
  // Every value reads back as the very double computed: 0.1 + 0.2 is not 0.3.
  EXPECT_EQ(std::stod("0.30000000000000004"), 0.1 + 0.2);
}

TEST(ModelTemplate, DefinitionsAndDefaults) {
  const std::string text =
      "# w = {w ?= 0.05}, A = {A = w*t}\n"
      "EM 1 {7800*A}\n";
  const ModelTemplate t(text, "a.dat");
  t.check({"t"});
  flexmb::io::ParameterValues defined;
  EXPECT_EQ(t.instantiate({{"t", 2e-4}}, &defined), "# w = 0.05, A = 1e-05\nEM 1 0.078\n");
  EXPECT_EQ(defined, (flexmb::io::ParameterValues{{"w", 0.05}, {"A", 1e-5}}));
  // The study overrides a default.
  t.check({"t", "w"});
  EXPECT_EQ(t.instantiate({{"t", 2e-4}, {"w", 0.1}}), "# w = 0.1, A = 2e-05\nEM 1 0.156\n");
  EXPECT_EQ(t.placeholders().size(), 3u);
  EXPECT_EQ(t.placeholders()[1].kind, ModelTemplate::Placeholder::Kind::Define);
  EXPECT_EQ(t.placeholders()[1].name, "A");
  EXPECT_EQ(t.placeholders()[2].line, 2);
}

TEST(ModelTemplate, ComparisonsAreNotDefinitions) {
  const ModelTemplate t("ITERSTEP 10 {t >= 1 ? 20 : 10}\nX 1 {t == 2}\n", "a.dat");
  t.check({"t"});
  EXPECT_EQ(t.instantiate({{"t", 2}}), "ITERSTEP 10 20\nX 1 1\n");
}

TEST(ModelTemplate, UnknownParameterNamesTheLineAndSuggests) {
  const ModelTemplate t("X 1 0 0\nESTIFF 1 {E*bb*h}\n", "beam.dat");
  const std::string e = errorOf([&] { t.check({"E", "b", "h"}); });
  EXPECT_NE(e.find("beam.dat:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown parameter 'bb'"), std::string::npos) << e;
  EXPECT_NE(e.find("E, b, h"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'b'"), std::string::npos) << e;
}

TEST(ModelTemplate, NameUsedBeforeItsDefinition) {
  const ModelTemplate t("X 1 {2*A}\n% {A = t*t}\n", "m.dat");
  const std::string e = errorOf([&] { t.check({"t"}); });
  EXPECT_NE(e.find("m.dat:1:"), std::string::npos) << e;
  EXPECT_NE(e.find("defined later, at line 2"), std::string::npos) << e;
}

TEST(ModelTemplate, BadExpressionGivesMuParsersReason) {
  const ModelTemplate t("\n\nXF 3 {2*}\n", "m.dat");
  const std::string e = errorOf([&] { t.check({"P"}); });
  EXPECT_NE(e.find("m.dat:3: bad expression {2*}"), std::string::npos) << e;
  // Two results (a comma) are an error too.
  const ModelTemplate u("XF 3 {P, 2}\n", "m.dat");
  EXPECT_NE(errorOf([&] { u.check({"P"}); }).find("m.dat:1: bad expression {P, 2}"), std::string::npos);
}

TEST(ModelTemplate, SyntaxErrorsOfThePlaceholders) {
  EXPECT_NE(errorOf([] { ModelTemplate("X 1 0\nX 2 {t 0\n", "m.dat"); }).find("m.dat:2: a '{' without '}'"),
            std::string::npos);
  EXPECT_NE(errorOf([] { ModelTemplate("X 1 t} 0\n", "m.dat"); }).find("m.dat:1: a '}' without '{'"),
            std::string::npos);
  EXPECT_NE(errorOf([] { ModelTemplate("X 1 { } 0\n", "m.dat"); }).find("m.dat:1: an empty placeholder"),
            std::string::npos);
  EXPECT_NE(errorOf([] { ModelTemplate("X 1 {{t}} 0\n", "m.dat"); }).find("m.dat:1:"), std::string::npos);
  EXPECT_NE(errorOf([] { ModelTemplate("% {status = 1}\n", "m.dat"); }).find("cannot be defined"), std::string::npos);
}

TEST(ModelTemplate, ParametersTheTemplateDoesNotUseAreAnError) {
  const ModelTemplate t("X 1 {t}\n", "m.dat");
  const std::string e = errorOf([&] { t.check({"t", "L"}); });
  EXPECT_NE(e.find("m.dat: the parameter 'L' is not used"), std::string::npos) << e;
}

TEST(ModelTemplate, RedefiningAParameterIsAnError) {
  const ModelTemplate t("% {t = 2}\nX 1 {t}\n", "m.dat");
  const std::string e = errorOf([&] { t.check({"t"}); });
  EXPECT_NE(e.find("m.dat:1:"), std::string::npos) << e;
  EXPECT_NE(e.find("{t ?= 2}"), std::string::npos) << e;
}

TEST(ModelTemplate, NonFiniteValueNamesTheLineAndTheParameters) {
  const ModelTemplate t("X 1 0\nESTIFF 1 {1/(t-0.1)}\n", "m.dat");
  t.check({"t"});
  EXPECT_NO_THROW(t.instantiate({{"t", 0.2}}));
  const std::string e = errorOf([&] { t.instantiate({{"t", 0.1}}); });
  EXPECT_NE(e.find("m.dat:2: {1/(t-0.1)} gives inf at t = 0.1"), std::string::npos) << e;
  const std::string n = errorOf([&] { ModelTemplate("X 1 {sqrt(t)}\n", "m.dat").instantiate({{"t", -1}}); });
  EXPECT_NE(n.find("gives NaN"), std::string::npos) << n;
}

TEST(ModelTemplate, InstantiatedModelKeepsTheTemplatesLineNumbers) {
  // A reader error in an instantiated model names the template's line.
  const ModelTemplate t(
      "PLBEAM 1 1 101 2 102\nX 1 0 0\nX 2 {L} 0\nFIX 1\nFIX 101\nDYNE 1 1 2 3\nEND\nHALT\nEM 1 {rhoA}\nEND\nEND\n",
      "m.dat");
  t.check({"L", "rhoA"});
  try {
    flexmb::io::readDatString(t.instantiate({{"L", 1.0}, {"rhoA", -1.0}}), "m.dat");
    FAIL() << "a negative mass was read";
  } catch (const flexmb::io::DatError& e) {
    EXPECT_EQ(e.line(), 9) << e.what();
  }
}

TEST(ModelTemplate, FromFileNamesAMissingFile) {
  const std::string e = errorOf([] { ModelTemplate::fromFile("/nonexistent/x.dat"); });
  EXPECT_NE(e.find("/nonexistent/x.dat: cannot read"), std::string::npos) << e;
}

TEST(ModelTemplate, EvaluateExpression) {
  EXPECT_DOUBLE_EQ(flexmb::io::evaluateExpression("6*M/(w*t^2)", {{"M", 2}, {"w", 0.5}, {"t", 2}}), 6.0);
  EXPECT_THROW(flexmb::io::evaluateExpression("M*x", {{"M", 2}}), std::invalid_argument);
}
