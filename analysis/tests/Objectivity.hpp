#pragma once
// Objectivity of spatial models (issue 22): a model turned as a whole by a rotation R must give the
// turned answer. rotatedDat() turns a spatial .dat text the way a user would write the turned model;
// the comparisons below measure how far two solutions are from being each other's rotation.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/elements/EulerParameters.hpp"
#include "core/model/Model.hpp"
#include "io/formats/DatReader.hpp"

namespace flexmb::objectivity {

// A fixed "random" proper rotation (seeded, so a failure can be reproduced).
inline Eigen::Matrix3d randomRotation(unsigned seed = 2026) {
  std::mt19937 gen(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(gen), n(gen), n(gen), n(gen));
  q.normalize();
  return q.toRotationMatrix();
}

inline Eigen::Vector4d turned(const Eigen::Matrix3d& R, const Eigen::Vector4d& l) {
  const Eigen::Quaterniond r(R), p(l[0], l[1], l[2], l[3]);
  const Eigen::Quaterniond s = r * p;  // R(s) = R R(l)
  return {s.w(), s.x(), s.y(), s.z()};
}

// The model of `text` turned by R: X values of spatial position nodes, the direction vector of every
// element line whose type has one (BEAM y axis, HINGE axis, ...), XF / DELXF with three values
// (forces and global moments), GRAVITY, and the initial Euler parameters of every orientation node
// (X with four values or LAMBDA; a LAMBDA line q_R is added for nodes without one, so that body-frame
// data such as XM stay attached to the body). Throws std::invalid_argument for what a rotation does
// not carry over: roles of single position components (FIX n 1), forces on Euler parameters.
inline std::string rotatedDat(const std::string& text, const Eigen::Matrix3d& R) {
  const core::Model m = io::readDatString(text, "rotated.dat");
  auto kindOf = [&](int label) {
    const auto it = m.nodeByLabel.find(label);
    if (it == m.nodeByLabel.end()) throw std::invalid_argument("rotatedDat: unknown node " + std::to_string(label));
    return m.nodes[it->second].kind;
  };
  std::set<std::string> vectorTypes;
  for (const auto& t : core::elementTypes())
    if (!t.vector.empty()) vectorTypes.insert(t.keyword);
  std::set<int> eulerGiven;
  std::istringstream in(text);
  std::ostringstream out;
  out.precision(17);
  std::string line;
  bool inserted = false;
  auto number = [](const std::string& s) {
    std::string t = s;
    for (char& c : t)
      if (c == 'd' || c == 'D') c = 'e';
    return std::stod(t);
  };
  std::vector<std::string> pendingLambda;
  auto lambdaLines = [&]() {
    std::string s;
    for (const auto& n : m.nodes)
      if (n.kind == core::NodeKind::EulerParameters && !eulerGiven.count(n.label)) {
        const Eigen::Vector4d l = turned(R, m.x0.segment<4>(n.firstCoord));
        std::ostringstream o;
        o.precision(17);
        o << "LAMBDA " << n.label << " " << l[0] << " " << l[1] << " " << l[2] << " " << l[3] << "\n";
        s += o.str();
      }
    return s;
  };
  while (std::getline(in, line)) {
    std::string body = line;
    const size_t c = body.find_first_of("#%;");
    if (c != std::string::npos) body = body.substr(0, c);
    std::istringstream ls(body);
    std::vector<std::string> w;
    for (std::string t; ls >> t;) w.push_back(t);
    if (w.empty() || line[0] == '*') {
      out << line << "\n";
      continue;
    }
    std::string k = w[0];
    for (char& ch : k) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    auto vec3 = [&](size_t at) { return Eigen::Vector3d(number(w[at]), number(w[at + 1]), number(w[at + 2])); };
    auto emit = [&](const std::string& head, const Eigen::VectorXd& v) {
      out << head;
      for (Eigen::Index i = 0; i < v.size(); ++i) out << " " << v[i];
      out << "\n";
    };
    if (k == "END" && !inserted) {
      out << lambdaLines();
      inserted = true;
      out << line << "\n";
    } else if ((k == "X" || k == "XYZ") && w.size() == 5 &&
               kindOf(std::stoi(w[1])) == core::NodeKind::SpatialPosition) {
      emit(k + " " + w[1], R * vec3(2));
    } else if ((k == "X" && w.size() == 6) || k == "LAMBDA") {
      const int n = std::stoi(w[1]);
      if (kindOf(n) != core::NodeKind::EulerParameters) throw std::invalid_argument("rotatedDat: " + line);
      eulerGiven.insert(n);
      emit(k + " " + w[1], turned(R, Eigen::Vector4d(number(w[2]), number(w[3]), number(w[4]), number(w[5]))));
    } else if (vectorTypes.count(k) && w.size() >= 5) {
      std::string head = w[0];
      for (size_t i = 1; i + 3 < w.size(); ++i) head += " " + w[i];
      emit(head, R * vec3(w.size() - 3));
    } else if (k == "XF" || k == "DELXF") {
      if (w.size() != 5) throw std::invalid_argument("rotatedDat: only three-component loads turn: " + line);
      emit(k + " " + w[1], R * vec3(2));
    } else if (k == "GRAVITY") {
      emit(k, R * vec3(1));
    } else if ((k == "FIX" || k == "DYNX" || k == "INPUTX") && w.size() > 2 &&
               kindOf(std::stoi(w[1])) == core::NodeKind::SpatialPosition && w.size() != 5) {
      throw std::invalid_argument("rotatedDat: a role of single position components does not turn: " + line);
    } else {
      out << line << "\n";
    }
  }
  return out.str();
}

// Largest distance between two configurations of the same model text, one of them turned by R:
// |R p_a - p_b| over the position nodes (relative to `length`) and |R R(lambda_a) - R(lambda_b)|
// (Frobenius) over the orientation nodes, |w_a - w_b| length over BEAMW's warping nodes.
inline double configurationDifference(const core::Model& a, const Eigen::VectorXd& xa, const core::Model& b,
                                      const Eigen::VectorXd& xb, const Eigen::Matrix3d& R, double length) {
  double worst = 0.0;
  for (const auto& na : a.nodes) {
    const core::Node& nb = b.nodes[b.nodeByLabel.at(na.label)];
    if (na.kind == core::NodeKind::SpatialPosition) {
      worst = std::max(worst, (R * xa.segment<3>(na.firstCoord) - xb.segment<3>(nb.firstCoord)).norm() / length);
    } else if (na.kind == core::NodeKind::EulerParameters) {
      const Eigen::Matrix3d Ra = core::euler::rotation(xa.segment<4>(na.firstCoord).normalized());
      const Eigen::Matrix3d Rb = core::euler::rotation(xb.segment<4>(nb.firstCoord).normalized());
      worst = std::max(worst, (R * Ra - Rb).norm());
    } else if (na.kind == core::NodeKind::Warping) {  // a rate of twist: the same in any orientation
      worst = std::max(worst, std::abs(xa[na.firstCoord] - xb[nb.firstCoord]) * length);
    }
  }
  return worst;
}

// A nodal mode shape dx at x as global motions: per position node its displacement, per orientation
// node its rotation 2 E(lambda) d lambda, turned by R (a warping node: its rate, as it is); stacked
// by node label.
inline Eigen::VectorXd globalShape(const core::Model& m, const Eigen::VectorXd& x, const Eigen::VectorXd& dx,
                                   const Eigen::Matrix3d& R) {
  std::map<int, Eigen::Vector3d> parts;
  for (const auto& n : m.nodes) {
    if (n.kind == core::NodeKind::SpatialPosition)
      parts[n.label] = R * dx.segment<3>(n.firstCoord);
    else if (n.kind == core::NodeKind::EulerParameters)
      parts[n.label] =
          R * (2.0 * core::euler::globalRateMatrix(x.segment<4>(n.firstCoord)) * dx.segment<4>(n.firstCoord));
    else if (n.kind == core::NodeKind::Warping)  // a scalar: not turned
      parts[n.label] = Eigen::Vector3d(dx[n.firstCoord], 0.0, 0.0);
  }
  Eigen::VectorXd v(3 * parts.size());
  int i = 0;
  for (const auto& [label, p] : parts) v.segment<3>(3 * i++) = p;
  return v;
}

// How far the turned modes of a are from lying in the span of b's modes of the same frequency
// (relative 1e-6; degenerate pairs compare as subspaces): the largest 1 - |projection| over a's modes.
inline double modeDifference(const core::Model& a, const Eigen::VectorXd& xa, const Eigen::MatrixXd& modesA,
                             const Eigen::VectorXd& omegaA, const core::Model& b, const Eigen::VectorXd& xb,
                             const Eigen::MatrixXd& modesB, const Eigen::VectorXd& omegaB, const Eigen::Matrix3d& R) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < modesA.cols(); ++i) {
    const Eigen::VectorXd u = globalShape(a, xa, modesA.col(i), R).normalized();
    std::vector<Eigen::VectorXd> span;
    for (Eigen::Index j = 0; j < modesB.cols(); ++j)
      if (std::abs(omegaB[j] - omegaA[i]) <= 1e-6 * std::abs(omegaA[i]) + 1e-12)
        span.push_back(globalShape(b, xb, modesB.col(j), Eigen::Matrix3d::Identity()));
    if (span.empty()) return 1.0;
    Eigen::MatrixXd B(u.size(), static_cast<Eigen::Index>(span.size()));
    for (size_t j = 0; j < span.size(); ++j) B.col(static_cast<Eigen::Index>(j)) = span[j];
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(B);
    const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(u.size(), B.cols());
    worst = std::max(worst, 1.0 - (Q.transpose() * u).norm());
  }
  return worst;
}

}  // namespace flexmb::objectivity
