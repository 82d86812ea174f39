// The mode-9 transfer block (issue 21 item 3, bad input): every channel is checked against the
// model's roles when the file is read, and a wrong one is an error naming file:line and the reason.
#include <gtest/gtest.h>

#include <string>

#include "io/formats/DatReader.hpp"

using namespace flexmb;

namespace {

// A truss from node 1 (clamped, or moved: INPUTX) to node 2 (sliding along x), and a hinge-free
// orientation node 4 on a PLBEAM from node 2 to node 3; then the transfer block `block` at line 15.
std::string model(const std::string& block) {
  return "PLTRUSS 1 1 2\n"     // 1
         "PLBEAM 2 2 4 3 5\n"  // 2
         "X 1 0 0\n"           // 3
         "X 2 1 0\n"           // 4
         "X 3 2 0\n"           // 5
         "INPUTX 1 1\n"        // 6
         "FIX 1 2\n"           // 7
         "FIX 2 2\n"           // 8
         "DYNE 1 1\n"          // 9
         "DYNE 2 1 2 3\n"      // 10
         "END\nHALT\n"         // 11-12
         "ESTIFF 1 10\nEND\n"  // 13-14
         "HALT\n" +            // 15
         block +
         "END\nEND\n";  // from 16
}

std::string errorOf(const std::string& text) {
  try {
    io::readDatString(text, "tf.dat");
  } catch (const io::DatError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST(DatTransfer, ChannelsAreResolved) {
  const core::Model m = io::readDatString(
      model("INPUTF 1 3 2\nINX 2 1 1\nINPUTF 3 5 1\nOUTX 2 3 1\nOUTXP 1 2 1\nOUTF 3 1 1\nOUTF 4 1 2\n"), "tf.dat");
  ASSERT_EQ(m.transferInputs.size(), 3u);
  ASSERT_EQ(m.transferOutputs.size(), 4u);
  using K = core::TransferChannel::Kind;
  EXPECT_EQ(m.transferInputs[1].kind, K::Motion);
  EXPECT_EQ(m.transferInputs[2].kind, K::Force);      // a moment on the planar orientation node 5
  EXPECT_EQ(m.transferOutputs[0].kind, K::Velocity);  // sorted by channel number
  EXPECT_EQ(m.transferOutputs[0].line, 20);
  EXPECT_EQ(m.transferOutputs[1].coord, m.nodes[m.nodeByLabel.at(3)].firstCoord);
  EXPECT_EQ(m.transferOutputs[3].component, 2);
}

TEST(DatTransfer, BadChannelsNameTheLineAndTheReason) {
  struct Case {
    std::string block, message;
  };
  const Case cases[] = {
      {"INPUTF 1 9 1\nOUTX 1 3 1\n", "tf.dat:16: INPUTF: node 9 does not exist"},
      {"INPUTF 1 3 1\nOUTX 1 7 1\n", "tf.dat:17: OUTX: node 7 does not exist"},
      {"INPUTF 1 2 2\nOUTX 1 3 1\n", "tf.dat:16: INPUTF: coordinate 2 of node 2 is fixed: not a load point"},
      {"INPUTF 1 1 1\nOUTX 1 3 1\n",
       "tf.dat:16: INPUTF: coordinate 1 of node 1 is an input coordinate (INPUTX): not a load point (its "
       "prescribed motion takes any force there)"},
      {"INPUTF 1 3 1\nOUTX 1 1 2\n", "tf.dat:17: OUTX: coordinate 2 of node 1 is fixed: it does not move"},
      {"INPUTF 1 3 1\nOUTXP 1 2 2\n", "tf.dat:17: OUTXP: coordinate 2 of node 2 is fixed"},
      {"INX 1 3 1\nOUTX 1 3 1\n", "tf.dat:16: INX: coordinate 1 of node 3 is free: INX needs"},
      {"INPUTF 1 3 1\nOUTF 1 3 2\n", "tf.dat:17: OUTF: coordinate 2 of node 3 is free: the force there is the applied"},
      {"INPUTF 1 3 3\nOUTX 1 3 1\n", "tf.dat:16: INPUTF: node 3 has 2 components, not 3"},
      {"INPUTF 1 3 1\nINPUTF 1 3 2\nOUTX 1 3 1\n", "tf.dat:17: INPUTF: input 1 is given twice (also at line 16)"},
      {"INPUTF 2 3 1\nOUTX 1 3 1\n", "tf.dat:16: INPUTF: input numbers must run 1, 2, ... without gaps"},
      {"INPUTF 1 3 1\nOUTX 1 3 1 4\n", "tf.dat:17: OUTX: expected 3 integers"},
      {"INPUTF 1 3 1.5\nOUTX 1 3 1\n", "tf.dat:16: INPUTF: expected an integer for component"},
  };
  for (const Case& c : cases) {
    const std::string err = errorOf(model(c.block));
    EXPECT_TRUE(contains(err, c.message)) << "block:\n" << c.block << "error: " << err;
  }
}
