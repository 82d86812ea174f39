#pragma once
// Eigenfrequencies over a range of motion (paper Fig. 5): static equilibria with one nodal
// coordinate (or a spatial orientation node's rotation about a global axis) prescribed at equidistant values, held by a
// dead load along that coordinate (the load is the Lagrange multiplier of a bordered Newton system), and the natural
// frequencies of the free system in each, with modes tracked between neighbours by MAC.
#include <Eigen/Core>
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/model/Model.hpp"
#include "io/formats/CsvTable.hpp"

namespace flexmb::analysis {

struct SweepOptions {
  int node = 0;       // node label
  int component = 1;  // 1-based; on a spatial orientation node 1..3: its rotation about global x, y, z (rad)
  double from = 0.0, to = 0.0;
  int steps = 10;  // number of configurations (equidistant, both ends included)
  int nev = 4;
  std::optional<Eigen::MatrixXd> basis;  // q = V eta; empty = full model
  double t = 0.0;                        // time at which the loads of the file are taken (XF, XFT)
  // q indices held at zero in the eigenproblem (full models): the q_s subproblem of Eq. 21 that
  // reduction bases are built from (analysis::buildBasis reuses these modes), solved as
  // analysis::subproblemModes solves it (also when the list is empty). Not set: the whole model's
  // natural frequencies (analysis::naturalFrequencies).
  std::optional<std::vector<int>> heldCoordinates;
  std::function<void(int done, int total)> onPoint;  // progress: called before each point's eigenproblem
  // Set asynchronously (Ctrl-C): the sweep stops before its next continuation step and keeps the
  // points reached (analysis/Interrupt.hpp); interruptSignal names the signal.
  const std::atomic<bool>* interrupt = nullptr;
  const std::atomic<int>* interruptSignal = nullptr;
};

struct SweepPoint {
  double value = 0.0;           // the prescribed coordinate
  double load = 0.0;            // the dead load that holds it
  Eigen::VectorXd eta, q;       // configuration
  Eigen::VectorXd x;            // its nodal coordinates (nx)
  Eigen::VectorXd omega;        // rad/s, tracked order (column j continues column j of the previous point)
  Eigen::VectorXd omegaSorted;  // rad/s, ascending (the i-th eigenfrequency, as the paper plots it)
  Eigen::MatrixXd modes;        // in q coordinates (nq x nev), tracked order, unit Euclidean length
  // The eigenvectors in q as the eigensolver gave them (ascending frequencies, omegaSorted; not
  // normalised; zero at heldCoordinates), for reduction bases.
  Eigen::MatrixXd modesAscending;
  // What a designer reads besides (issue 53 item 1): the deformations, the stresses (elastic and the
  // reaction stresses of the constrained deformations, in equilibrium with the file's initial loads
  // and the holding load) and the holding load as nodal forces (nx: `load` along the coordinate).
  Eigen::VectorXd e, sigma, holding;
};

struct SweepResult {
  std::string
      prescribed;  // what was prescribed, in words ("x(node 6, x)", "the rotation of node 4 about global z (rad)")
  std::vector<SweepPoint> points;
  bool completed = true;
  bool interrupted = false;  // stopped by SweepOptions::interrupt (then completed = false)
  std::string stopReason;
};

SweepResult sweep(const core::Model& model, const SweepOptions& options);
// The sweep as a table, the one every front end writes (`flexmb sweep`, the study): value, load,
// f1_Hz... ascending, tracked1_Hz... in tracked order (as many as any point has), every nodal
// coordinate.
// The sweep's table: value, load, frequencies (ascending, then tracked), the coordinates; with
// VISUALIZATION sections the largest von Mises stress and its element (max_stress,
// max_stress_element), then the support reactions R.* (analysis/StaticDesign.hpp), as static's.
io::CsvTable sweepTable(const core::Model& model, const SweepResult& result);
}  // namespace flexmb::analysis
