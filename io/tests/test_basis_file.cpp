// Basis files (io/formats/BasisFile): exact round trip of V and of the record of how it was made, and the
// "file:line: reason" errors on malformed input.
#include "io/formats/BasisFile.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using namespace flexmb::io;

namespace {

class BasisFile : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "flexmb_basis_XXXXXX").string();
    ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string writeText(const std::string& name, const std::string& text) const {
    const std::string p = path(name);
    std::ofstream f(p, std::ios::binary);
    f << text;
    return p;
  }
  static std::string readText(const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  }

  // readBasis must throw std::runtime_error whose message starts with "<path>:<line>: " and
  // contains `reason`.
  void expectReadError(const std::string& text, int line, const std::string& reason) {
    const std::string p = writeText("bad.csv", text);
    try {
      readBasis(p);
      ADD_FAILURE() << "no exception for:\n" << text;
    } catch (const std::runtime_error& e) {
      const std::string msg = e.what();
      const std::string prefix = p + ":" + std::to_string(line) + ": ";
      EXPECT_EQ(msg.rfind(prefix, 0), 0u) << "message: " << msg << "\nexpected prefix: " << prefix;
      EXPECT_NE(msg.find(reason), std::string::npos) << "message: " << msg;
    } catch (...) {
      ADD_FAILURE() << "wrong exception type for:\n" << text;
    }
  }

  fs::path dir_;
};

bool bitwiseEqual(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// 6 x 5 basis with large = {4, 1} (identity columns 0 and 1) and awkward doubles elsewhere.
MatrixXd sampleBasis() {
  MatrixXd V = MatrixXd::Zero(6, 5);
  V(4, 0) = 1.0;
  V(1, 1) = 1.0;
  std::mt19937_64 gen(12345);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  const int small[] = {0, 2, 3, 5};
  for (int k = 2; k < 5; ++k)
    for (int i : small) V(i, k) = d(gen) * std::pow(10.0, (i * 7 + k * 3) % 40 - 20);
  V(0, 2) = -0.0;
  V(2, 2) = std::numeric_limits<double>::denorm_min();
  V(3, 2) = std::numeric_limits<double>::max();
  V(5, 2) = 0.1;
  V(0, 3) = 1.0 / 3.0;
  V(2, 3) = -std::numeric_limits<double>::min();
  V(3, 3) = 1e-300;
  return V;
}

BasisInfo sampleInfo() {
  BasisInfo info;
  info.method = "svd-modal";
  info.model = "models/straight guidance.dat";
  info.parameters = {{"r", "4"},
                     {"a", "1"},
                     {"threshold", "0.01"},
                     {"configurations", "5"},
                     {"note", "q = V eta, sweep 0..0.05 m: ok"},
                     {"empty", ""}};
  info.large = {4, 1};
  info.scaledSingularValues = VectorXd(4);
  info.scaledSingularValues << 0.61234567890123456, 0.25, 1.0 / 7.0, 1e-17;
  return info;
}

const char* kHead = "# flexmb basis\n# method: modal\n# model: m.dat\n";  // lines 1-3

}  // namespace

TEST_F(BasisFile, RoundTripExact) {
  const MatrixXd V = sampleBasis();
  const BasisInfo info = sampleInfo();
  const std::string p = path("basis.csv");
  writeBasis(p, V, info);

  BasisInfo back;
  back.method = "stale";
  back.parameters = {{"stale", "x"}};
  const MatrixXd W = readBasis(p, &back);
  ASSERT_EQ(W.rows(), V.rows());
  ASSERT_EQ(W.cols(), V.cols());
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (Eigen::Index j = 0; j < V.cols(); ++j)
      EXPECT_TRUE(bitwiseEqual(W(i, j), V(i, j))) << i << "," << j << ": " << W(i, j);
  EXPECT_TRUE(std::signbit(W(0, 2)));  // -0 kept

  EXPECT_EQ(back.method, info.method);
  EXPECT_EQ(back.model, info.model);
  EXPECT_EQ(back.parameters, info.parameters);
  EXPECT_EQ(back.large, info.large);
  ASSERT_EQ(back.scaledSingularValues.size(), info.scaledSingularValues.size());
  for (Eigen::Index k = 0; k < info.scaledSingularValues.size(); ++k)
    EXPECT_TRUE(bitwiseEqual(back.scaledSingularValues[k], info.scaledSingularValues[k]));

  // Without info, and as a string.
  EXPECT_EQ(readBasis(p), W);
  EXPECT_EQ(parseBasis(formatBasis(V, info), "mem"), W);
}

TEST_F(BasisFile, LayoutOfTheFile) {
  MatrixXd V(3, 2);
  V << 1, 0,   //
      0, 0.5,  //
      0, -0.25;
  BasisInfo info;
  info.method = "modal";
  info.model = "two_link.dat";
  info.parameters = {{"r", "1"}};
  info.large = {0};
  const std::string p = path("modal.csv");
  writeBasis(p, V, info);
  EXPECT_EQ(readText(p),
            "# flexmb basis\n"
            "# method: modal\n"
            "# model: two_link.dat\n"
            "# size: 3 x 2\n"
            "# r: 1\n"
            "# large: 0\n"
            "1,0\n"
            "0,0.5\n"
            "0,-0.25\n");
  BasisInfo back;
  readBasis(p, &back);
  EXPECT_EQ(back.scaledSingularValues.size(), 0);

  // Empty large list and no model: still reads back.
  BasisInfo bare;
  bare.method = "manual";
  writeBasis(p, V, bare);
  BasisInfo b2;
  EXPECT_EQ(readBasis(p, &b2), V);
  EXPECT_EQ(b2.method, "manual");
  EXPECT_EQ(b2.model, "");
  EXPECT_TRUE(b2.large.empty());
  EXPECT_TRUE(b2.parameters.empty());
}

TEST_F(BasisFile, TolerantReading) {
  // CRLF, blanks around fields, blank lines, '+' signs, exponents, no size line, BOM.
  const std::string text =
      "\xEF\xBB\xBF#flexmb basis\r\n"
      "#   method:   modal  \r\n"
      "\r\n"
      "# large: 1\r\n"
      " 0 , +1.5e-3\r\n"
      "1,\t0\r\n"
      "\r\n"
      "0 , -2E+2\r\n";
  BasisInfo info;
  const MatrixXd V = parseBasis(text, "t", &info);
  ASSERT_EQ(V.rows(), 3);
  ASSERT_EQ(V.cols(), 2);
  EXPECT_EQ(V(0, 1), 1.5e-3);
  EXPECT_EQ(V(1, 0), 1.0);
  EXPECT_EQ(V(2, 1), -200.0);
  EXPECT_EQ(info.method, "modal");
  EXPECT_EQ(info.large, (std::vector<int>{1}));
}

TEST_F(BasisFile, MalformedFilesThrowWithLineNumbers) {
  const std::string h = kHead;
  expectReadError("", 1, "empty file");
  expectReadError("\n  \n\n", 1, "empty file");
  expectReadError("1,2\n3,4\n", 1, "missing header");
  expectReadError("# method: modal\n1,2\n", 1, "missing header");
  expectReadError("\n# flexmb basiss\n1\n", 2, "missing header");
  expectReadError(h + "1,2\n3,4,5\n", 5, "ragged row: 3 values, expected 2 (as in line 4)");
  expectReadError(h + "1,2,3\n4,5\n6,7,8\n", 5, "ragged row");
  expectReadError(h + "1,2\nabc,4\n", 5, "field 1 'abc' is not a finite number");
  expectReadError(h + "1,2x\n", 4, "field 2 '2x' is not a finite number");
  expectReadError(h + "1,nan\n", 4, "not a finite number");
  expectReadError(h + "1,inf\n", 4, "not a finite number");
  expectReadError(h + "1,1e999\n", 4, "not a finite number");
  expectReadError(h + "1,,2\n", 4, "empty field 2");
  expectReadError(h + "1,2,\n", 4, "empty field 3");
  expectReadError(h + "1 2\n", 4, "field 1 '1 2' is not a finite number");
  expectReadError(h, 3, "no data rows");
  expectReadError(h + "\n", 4, "no data rows");
  expectReadError(h + "1,2\n# large: 0\n", 5, "header line after the data rows");
  expectReadError(h + "# just a remark\n1\n", 4, "expected a header line '# key: value'");
  expectReadError(h + "# : x\n1\n", 4, "empty key");
  expectReadError(h + "# method: svd\n1\n", 4, "duplicate 'method'");
  expectReadError(h + "# r: 1\n# r: 2\n1\n", 5, "duplicate parameter 'r'");
  expectReadError(h + "# size: 2 x 2\n1,0\n", 5, "1 data rows but the size line (line 4) says 2");
  expectReadError(h + "# size: 1 x 3\n1,0\n", 5, "row has 2 values but the size line");
  expectReadError(h + "# size: two by two\n1\n", 4, "size must be");
  expectReadError(h + "# large: 0 x\n1\n", 4, "large index 'x'");
  expectReadError(h + "# large: -1\n1\n", 4, "large index '-1'");
  expectReadError(h + "# large: 2\n1,0\n0,1\n", 4, "large index 2 out of range");
  expectReadError(h + "# large: 0 0\n1,0\n0,1\n", 4, "duplicate large index 0");
  expectReadError(h + "# large: 0 1 0\n1,0\n0,1\n", 4, "3 large coordinates but V has only 2");
  expectReadError(h + "# large: 1\n1,0\n0,1\n", 4, "column 0 of V is not the unit vector");
  expectReadError(h + "# singular values: 0.5 x\n1\n", 4, "singular value 'x'");
}

TEST_F(BasisFile, GarbageNeverCrashes) {
  std::mt19937 gen(7);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int trial = 0; trial < 200; ++trial) {
    std::string text = trial % 2 ? std::string(kHead) : std::string();
    const int n = 1 + trial * 3;
    for (int i = 0; i < n; ++i) {
      int b = byte(gen);
      // Bias towards characters the parser cares about.
      const char special[] = {',', '\n', '#', ':', '1', '-', 'e', '.', ' ', '\r', '\0'};
      if (b < 110) b = special[b % 11];
      text.push_back(static_cast<char>(b));
    }
    try {
      parseBasis(text, "garbage");
    } catch (const std::runtime_error&) {}
  }
  // Nonexistent file.
  EXPECT_THROW(readBasis(path("does_not_exist.csv")), std::runtime_error);
}

TEST_F(BasisFile, WriterRejectsBadInput) {
  const MatrixXd V = sampleBasis();
  const std::string p = path("rejected.csv");
  auto expectReject = [&](const MatrixXd& M, const BasisInfo& info, const std::string& reason) {
    try {
      writeBasis(p, M, info);
      ADD_FAILURE() << "no exception, expected: " << reason;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(p)) << "nothing may be written: " << reason;
  };
  BasisInfo info = sampleInfo();
  expectReject(MatrixXd(0, 3), info, "at least one row");
  MatrixXd nanV = V;
  nanV(3, 4) = std::nan("");
  expectReject(nanV, info, "V(3, 4)");
  BasisInfo i2 = info;
  i2.method = "";
  expectReject(V, i2, "method is empty");
  i2 = info;
  i2.model = "a\nb";
  expectReject(V, i2, "line break");
  i2 = info;
  i2.model = "trailing ";
  expectReject(V, i2, "leading or trailing blanks");
  i2 = info;
  i2.parameters.push_back({"a:b", "1"});
  expectReject(V, i2, "contains ':'");
  i2 = info;
  i2.parameters.push_back({"large", "1"});
  expectReject(V, i2, "reserved");
  i2 = info;
  i2.parameters.push_back({"r", "5"});
  expectReject(V, i2, "duplicate parameter key 'r'");
  i2 = info;
  i2.large = {4, 2};
  expectReject(V, i2, "column 1 of V is not the unit vector of large index 2");
  i2 = info;
  i2.large = {4, 6};
  expectReject(V, i2, "out of range");
  i2 = info;
  i2.scaledSingularValues[1] = std::numeric_limits<double>::infinity();
  expectReject(V, i2, "singular value 1");

  // Unwritable location: runtime_error naming the path.
  const std::string nowhere = path("no_such_dir/basis.csv");
  try {
    writeBasis(nowhere, V, info);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(nowhere), std::string::npos) << e.what();
  }
}
