// A catalogue of malformed .dat inputs: each must throw io::DatError naming the right line, with a
// message holding the expected text. Then a fuzz-ish pass: truncations, deleted lines and byte
// mutations of every valid and malformed text must parse or throw DatError, nothing else.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "io/formats/DatReader.hpp"

using namespace flexmb;
namespace fs = std::filesystem;

namespace {

std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

// Base model, kinematic lines 1-5.
const std::vector<std::string> kKin = {"PLBEAM 1 1 2 3 4", "X 3 1 0", "FIX 1", "FIX 2", "DYNE 1 2 3"};

// Kinematic block from line 1, then END HALT.
std::string kin(const std::vector<std::string>& lines) { return join(lines) + "END\nHALT\n"; }
// SPACAR 2013+: base kinematic block, END HALT (lines 6-7), dynamic lines from line 8, END END.
std::string dyn(const std::vector<std::string>& lines) {
  return join(kKin) + "END\nHALT\n" + join(lines) + "END\nEND\n";
}
// SPACAR95: base kinematic block, END (line 6), dynamic lines from line 7, END.
std::string s95(const std::vector<std::string>& lines) { return join(kKin) + "END\n" + join(lines) + "END\n"; }

struct Case {
  std::string name;
  std::string text;
  int line;
  std::string needle;
};

std::vector<Case> catalogue() {
  const std::string Q = "\"";
  return {
      {"missing_arguments", kin({"PLBEAM 1 1 2 3"}), 1,
       "PLBEAM: expected 5 integers (element, node p, orientation p, node q, orientation q), found 4"},
      {"too_many_arguments", kin({"PLBEAM 1 1 2 3 4 5"}), 1, "found 6"},
      {"missing_mass", dyn({"XM 3"}), 8,
       "XM: expected 2 to 7 numbers (node, mass, [Ixy], [Ixz], [Iyy], [Iyz], [Izz]), found 1"},
      {"too_many_inertia", dyn({"EM 1 1 2 3"}), 8, "PLBEAM 1 takes 1 or 2 mass parameters (rhoA, rhoI), found 3"},
      {"end_with_argument", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "END 5"}), 3, "expected no arguments, found 1"},
      {"orientation_node_as_position", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "PLTRUSS 2 3 2"}), 3,
       "node 2 is used as a position node here (PLTRUSS 2, node q) but as an orientation node by "
       "PLBEAM 1 (orientation p) at line 1"},
      {"position_node_as_orientation", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "PLHINGE 2 3 4"}), 3,
       "node 3 is used as an orientation node here"},
      {"xy_on_orientation_node", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "XY 2 1 0"}), 3, "node 2 is an orientation node"},
      {"beta_on_position_node", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "BETA 3 0.1"}), 3, "node 3 is a position node"},
      // (A FIX of a node no element uses fixes nothing: a note, io/tests/test_dat_spacar.cpp.)
      {"undefined_node_input", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "INPUTX 9 1"}), 3,
       "INPUTX: node 9 is not used by any element"},
      {"undefined_node_mass", dyn({"XM 9 1.0"}), 8, "node 9 is not used by any element"},
      {"undefined_element_dyne", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "DYNE 7 1"}), 3, "DYNE: element 7 is not defined"},
      {"undefined_element_estiff", dyn({"ESTIFF 5 1 2"}), 8, "ESTIFF: element 5 is not defined"},
      {"duplicate_element", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "X 5 2 0", "PLBEAM 1 3 4 5 6"}), 4,
       "element 1 is already defined (PLBEAM 1 at line 1)"},
      {"bad_number_dots", kin({"PLBEAM 1 1 2 3 4", "X 3 1.2.3 0"}), 2, "expected a number for c1, found '1.2.3'"},
      {"bad_number_word", dyn({"ESTIFF 1 abc 10"}), 8, "expected a number for parameter, found 'abc'"},
      {"integer_expected_node", kin({"PLBEAM 1 1.5 2 3 4"}), 1, "expected an integer for node p, found '1.5'"},
      {"integer_expected_component", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "DYNE 1 2.5"}), 3,
       "expected an integer for component, found '2.5'"},
      {"unknown_keyword_suggestion", kin({"PLBEEM 1 1 2 3 4"}), 1, "unknown keyword 'PLBEEM'; did you mean PLBEAM?"},
      {"unknown_keyword", dyn({"FOOBARQ 1"}), 8, "unknown keyword 'FOOBARQ'"},
      {"beam_without_y_axis", kin({"BEAM 1 1 2 3 4"}), 1,
       "BEAM: expected 8 numbers (element, node p, orientation p, node q, orientation q, y1, y2, y3), found 5"},
      {"planar_and_spatial", kin({"PLBEAM 1 1 2 3 4", "BEAM 2 5 6 7 8 0 1 0"}), 2,
       "planar and spatial elements cannot be mixed in one model: planar PLBEAM 1 (line 1) and spatial BEAM 2 (line "
       "2)"},
      {"unsupported_plwheel", kin({"PLWHEEL 1 1 2 3"}), 1, "not supported by flexmb yet"},
      {"userinp_not_a_name", dyn({"USERINP 1"}), 8,
       "expected a MATLAB function name for MATLAB function name, found '1'"},
      {"usersig_without_name", dyn({"USERSIG"}), 8, "expected 1 argument (MATLAB function name)"},
      {"missing_end_dynamic", join(kKin) + "END\nHALT\nXM 3 1\n", 8,
       "end of file inside the dynamic block (begun at line 8): missing END"},
      {"missing_end_kinematic", "PLBEAM 1 1 2 3 4\nX 3 1 0\nFIX 1\n", 3,
       "end of file inside the kinematic block (begun at line 1): missing END"},
      {"missing_end_s95_second_block", join(kKin) + "END\nMASS 3 1\nEND\nHMAX 1\n", 9, "missing END"},
      {"eof_inside_block", "PLBEAM 1 1 2 3 4\nX 3 1 0\nEOF\n", 3,
       "EOF: inside the first block (begun at line 1): missing END"},
      {"halt_inside_block", "PLBEAM 1 1 2 3 4\nX 3 1 0\nHALT\n", 3,
       "HALT: inside the first block (begun at line 1): missing END"},
      {"expression_unbalanced", dyn({"XFT 3 1 " + Q + "sin(t" + Q}), 8, "invalid expression for f(t)"},
      {"expression_unknown_variable", dyn({"XFT 3 1 " + Q + "2*x" + Q}), 8, "invalid expression for f(t) \"2*x\""},
      {"expression_two_values", dyn({"XFT 3 1 " + Q + "1,2" + Q}), 8, "values"},
      {"expression_unquoted", dyn({"XFT 3 1 sin(t)"}), 8, "expected a quoted expression for f(t)"},
      {"unterminated_string", dyn({"XFT 3 1 " + Q + "sin(t)"}), 8, "unterminated quoted string"},
      {"inputxt_missing_expression", dyn({"INPUTXT 3 1 " + Q + "t" + Q + " " + Q + "1" + Q}), 8,
       "expected 5 arguments"},
      {"mixed_dialects", dyn({"EM 1 1", "MASS 3 1"}), 9,
       "the file mixes the dialects: MASS (line 9) is SPACAR95 only, EM (line 8) is SPACAR 2013+ only"},
      {"component_out_of_range_dyne", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "DYNE 1 4"}), 3,
       "component 4 out of range: PLBEAM 1 has 3 deformations"},
      {"component_out_of_range_inputx", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "INPUTX 3 3"}), 3,
       "component 3 out of range: node 3 is a position node"},
      {"component_zero", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "FIX 1 0"}), 3,
       "expected a positive integer for component, found '0'"},
      {"keyword_too_long", kin({"PLBEAMXYZ 1 1 2 3 4"}), 1, "longer than 8 characters"},
      {"stiffness_count", dyn({"ESTIFF 1 1e6"}), 8, "PLBEAM 1 takes 2 stiffness parameters (EA, EI), found 1"},
      {"damping_count", dyn({"ESTIFF 1 1 2", "EDAMP 1 1 2 3"}), 9, "takes 2 damping parameters"},
      {"negative_mass", dyn({"XM 3 -1"}), 8, "negative mass"},
      {"negative_mass_per_length", dyn({"EM 1 -2"}), 8, "negative mass per unit length"},
      {"empty_file", "", 0, "the file is empty"},
      {"only_comments", "* star\n% percent\n\n   # hash\n", 0, "no statements"},
      {"timestep_zero_count", dyn({"TIMESTEP 1.0 0"}), 8,
       "expected a positive integer for number of output intervals, found '0'"},
      {"timestep_spacar95_order", dyn({"TIMESTEP 100 0.5"}), 8, "the SPACAR95 order n T would fit"},
      {"timestep_nonpositive_time", dyn({"TIMESTEP -1 10"}), 8, "must be larger than the start time"},
      {"timestep_too_many", dyn({"TIMESTEP 1 10 5"}), 8, "expected 2 numbers"},
      {"role_conflict_coordinate", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "FIX 3 1", "DYNX 3 1"}), 4,
       "it was made fixed at line 3"},
      {"role_conflict_deformation", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "DYNE 1 2", "INPUTE 1 2"}), 4,
       "it was made dynamic at line 3"},
      {"kinematic_keyword_in_dynamic_block", dyn({"FIX 3"}), 8,
       "FIX: belongs to the kinematic block, which ended with END at line 6"},
      {"dynamic_keyword_in_kinematic_block", kin({"PLBEAM 1 1 2 3 4", "ESTIFF 1 1 1"}), 2,
       "belongs to a dynamic/static block"},
      {"input_values_not_input", dyn({"INPUTX 3 1 0.5"}), 8, "is not an input coordinate"},
      {"reference_on_fixed", dyn({"ESTIFF 1 1 1", "EREF 1 1 " + Q + "t" + Q}), 9, "is fixed"},
      {"zero_length_beam", kin({"PLBEAM 1 1 2 3 4"}), 1, "zero length"},
      {"node_label_zero", kin({"PLBEAM 1 0 2 3 4"}), 1, "expected a positive integer for node p, found '0'"},
      {"integer_overflow", kin({"PLBEAM 99999999999 1 2 3 4"}), 1, "out of range"},
      {"real_overflow", kin({"PLBEAM 1 1 2 3 4", "X 3 1e999 0"}), 2, "out of range"},
      {"coordinate_count", kin({"PLBEAM 1 1 2 3 4", "X 3 1"}), 2, "expected 2 coordinates"},
      {"force_on_orientation_node", dyn({"XF 2 1 1"}), 8, "orientation node"},
      {"quoted_keyword", kin({"\"PLBEAM\" 1 1 2 3 4"}), 1, "expected a keyword"},
      {"number_as_keyword", kin({"1 2 3"}), 1, "expected a keyword"},
      {"star_not_in_column_1", kin({"PLBEAM 1 1 2 3 4", " * comment"}), 2, "column 1"},
      {"invalid_keyword_characters", kin({"X=1"}), 1, "invalid keyword"},
      {"node_twice_in_element", kin({"PLTRUSS 1 1 1"}), 1, "appears twice"},
      {"no_elements", kin({"END"}), 1, "defines no elements"},
      {"s95_initial_value_on_fixed", s95({"E 1 1 0.5"}), 7, "initial values apply"},
      {"s95_xd_not_input", s95({"XD 3 1 1.0"}), 7, "is not an input coordinate"},
      {"s95_maxiterat_zero", s95({"MAXITERAT 0"}), 7, "positive integer"},
      {"startde_on_fixed", dyn({"STARTDE 1 1 0.1"}), 8, "is fixed: initial values apply"},
      {"iterstep_zero", dyn({"ITERSTEP 0 1"}), 8, "positive integer"},
      {"error_negative", dyn({"ERROR -1 1e-3"}), 8, "must be positive"},
      {"gravity_missing", dyn({"GRAVITY 0"}), 8, "expected 2 to 3 numbers"},
      {"dyne_without_element", kin({"PLBEAM 1 1 2 3 4", "X 3 1 0", "DYNE"}), 3,
       "expected at least 1 integer (element, [component ...]), found 0"},
  };
}

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() / ("flexmb_io_tests_" + std::to_string(::getpid()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = path_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Parses or throws DatError; anything else is a failure.
void parsesOrDatError(const std::string& text, const std::string& context) {
  try {
    io::readDatString(text, "fuzz.dat");
  } catch (const io::DatError&) {
  } catch (const std::exception& e) {
    ADD_FAILURE() << context << ": non-DatError exception: " << e.what() << "\n--- text ---\n" << text;
  } catch (...) {
    ADD_FAILURE() << context << ": unknown exception\n--- text ---\n" << text;
  }
}

std::vector<std::string> validTexts() {
  std::vector<std::string> v;
  for (const char* f : {"two_link_2013.dat", "slider_s95.dat"}) {
    std::ifstream in(std::string(FLEXMB_SOURCE_DIR) + "/io/tests/data/" + f, std::ios::binary);
    v.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    EXPECT_FALSE(v.back().empty()) << f;
  }
  v.push_back(dyn({"EM 1 2 0.1", "ESTIFF 1 1e6 10", "XM 3 1", "XFT 3 1 \"sin(t)\"", "TIMESTEP 1 10"}));
  v.push_back(s95({"EMASS 1 2", "ESTIFF 1 1e6 10", "MASS 3 1", "TIMESTEP 10 1", "EPSINT 1e-6"}));
  return v;
}

}  // namespace

TEST(Malformed, CatalogueHasEnoughEntries) { EXPECT_GE(catalogue().size(), 30u); }

TEST(Malformed, EachEntryThrowsDatErrorAtItsLine) {
  TempDir dir;
  for (const Case& c : catalogue()) {
    SCOPED_TRACE(c.name);
    const fs::path p = dir.write(c.name + ".dat", c.text);
    try {
      io::readDatFile(p.string());
      ADD_FAILURE() << c.name << ": no error\n--- text ---\n" << c.text;
    } catch (const io::DatError& e) {
      const std::string what = e.what();
      EXPECT_EQ(e.line(), c.line) << what;
      EXPECT_EQ(e.file(), p.string());
      EXPECT_NE(what.find(c.needle), std::string::npos) << "message: " << what << "\nexpected: " << c.needle;
      const std::string prefix = c.line > 0 ? p.string() + ":" + std::to_string(c.line) + ": " : p.string() + ": ";
      EXPECT_EQ(what.rfind(prefix, 0), 0u) << what;
      EXPECT_FALSE(e.message().empty());
    } catch (const std::exception& e) {
      ADD_FAILURE() << c.name << ": wrong exception type: " << e.what();
    }
  }
}

TEST(Malformed, ErrorNamesKeyword) {
  try {
    io::readDatString(kin({"PLBEAM 1 1 2 3"}), "model.dat");
    FAIL();
  } catch (const io::DatError& e) {
    EXPECT_EQ(e.file(), "model.dat");
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.keyword(), "PLBEAM");
    EXPECT_STREQ(e.what(),
                 "model.dat:1: PLBEAM: expected 5 integers (element, node p, orientation p, node q, "
                 "orientation q), found 4");
  }
  try {
    io::readDatString(dyn({"ESTIFF 5 1 2"}), "model.dat");
    FAIL();
  } catch (const io::DatError& e) {
    EXPECT_EQ(e.keyword(), "ESTIFF");  // builder errors get the keyword of their line too
  }
}

TEST(Malformed, FileNotFoundNamesThePath) {
  const std::string path = "/nonexistent-flexmb-dir/model_that_is_missing.dat";
  try {
    io::readDatFile(path);
    FAIL();
  } catch (const io::DatError& e) {
    EXPECT_EQ(e.line(), 0);
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
  TempDir dir;
  EXPECT_THROW(io::readDatFile(dir.path().string()), io::DatError);  // a directory
}

TEST(Malformed, TruncatedAndMutatedInputsNeverCrash) {
  std::vector<std::string> texts = validTexts();
  for (const Case& c : catalogue()) texts.push_back(c.text);
  size_t runs = 0;
  for (size_t t = 0; t < texts.size(); ++t) {
    const std::string& text = texts[t];
    // Truncate at every line boundary (keeping and dropping the newline).
    for (size_t i = 0; i <= text.size(); ++i) {
      if (i == text.size() || text[i] == '\n') {
        parsesOrDatError(text.substr(0, i), "truncation");
        parsesOrDatError(text.substr(0, std::min(i + 1, text.size())), "truncation");
        runs += 2;
      }
    }
    // Delete each line in turn.
    std::vector<std::string> lines;
    size_t pos = 0;
    while (pos <= text.size()) {
      size_t nl = text.find('\n', pos);
      if (nl == std::string::npos) nl = text.size();
      lines.push_back(text.substr(pos, nl - pos));
      pos = nl + 1;
    }
    for (size_t skip = 0; skip < lines.size(); ++skip) {
      std::string s;
      for (size_t k = 0; k < lines.size(); ++k)
        if (k != skip) s += lines[k] + "\n";
      parsesOrDatError(s, "deleted line");
      ++runs;
    }
  }
  // The valid files truncated at every byte.
  for (const std::string& text : validTexts())
    for (size_t i = 0; i <= text.size(); ++i, ++runs) parsesOrDatError(text.substr(0, i), "byte truncation");
  // Random byte mutations (fixed seed, reproducible).
  std::mt19937 rng(12345);
  const std::string alphabet = " \t\n\"%#;*,.-+eEdD0123456789ENDHALT\x01\xff";
  const auto valid = validTexts();
  for (int k = 0; k < 3000; ++k, ++runs) {
    std::string s = valid[k % valid.size()];
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int j = 0; j < edits && !s.empty(); ++j) {
      const size_t at = rng() % s.size();
      switch (rng() % 3) {
        case 0:
          s[at] = alphabet[rng() % alphabet.size()];
          break;
        case 1:
          s.erase(at, 1 + rng() % 8);
          break;
        default:
          s.insert(at, 1, alphabet[rng() % alphabet.size()]);
          break;
      }
    }
    parsesOrDatError(s, "mutation");
  }
  EXPECT_GT(runs, 1000u);
}

// A NUL byte in the VISUALIZATION section (found by flexmb_fuzz_dat in CI's sanitizer run: the word
// splitter looked each byte up with strchr, which finds a NUL in its own terminator, so a line with
// one never advanced and the reader filled memory until the fuzzer's time-out). A NUL belongs to its
// word: the model reads, a statement with one is noted with its line, the lines after it still count.
TEST(Malformed, NulBytesInTheVisualizationSectionAreWordCharacters) {
  using namespace std::string_literals;
  // Lines 1-5: the base kinematic block; 6: END; 7: VISUALIZATION.
  const std::string text = join(kKin) + "END\nVISUALIZATION\n" +
                           "BEAMPROPS 1\n"               // 8
                           "CROSSTYPE RECT\n"s +         // 9
                           "CROSS\0\aM 0.01 0.001\n"s +  // 10
                           "CROSSDIM 0.02 0.002\n"       // 11
                           "GRAPHICS 1\0\n"s +           // 12
                           "\0\n"s +                     // 13
                           "OPACITY 0.5\n";              // 14
  core::Model m;
  ASSERT_NO_THROW(m = io::readDatString(text, "v.dat"));
  auto noted = [&](const std::string& part) {
    for (const std::string& n : m.notes)
      if (n.find(part) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(noted("v.dat:10: VISUALIZATION: unknown statement")) << ::testing::PrintToString(m.notes);
  EXPECT_TRUE(noted("v.dat:12: VISUALIZATION: GRAPHICS: '1\0' is not an element number"s))
      << ::testing::PrintToString(m.notes);
  EXPECT_TRUE(noted("v.dat:13: VISUALIZATION: unknown statement")) << ::testing::PrintToString(m.notes);
  ASSERT_EQ(m.appearance.count(1), 1u);
  EXPECT_DOUBLE_EQ(m.appearance.at(1).width, 0.02);
  EXPECT_DOUBLE_EQ(m.appearance.at(1).thickness, 0.002);
  EXPECT_DOUBLE_EQ(m.appearance.at(1).opacity, 1.0);  // GRAPHICS named no element: OPACITY applies to none
}
