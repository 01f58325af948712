#pragma once
/// \file refine.hpp
/// \brief An optimum that proves itself (docs/optimize.md, "Path error" and "Mesh refinement"):
/// coarser equal meshes first (each solve warm-started from the last), the asked-for mesh, then
/// intervals split where the local path error is large until the path error meets the tolerance.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nhc/optimize/hermite_simpson.hpp"
#include "nhc/optimize/path_error.hpp"
#include "nhc/optimize/solve.hpp"

namespace nhc::optimize {

struct RefineOptions {
  int intervals = 40;            ///< the mesh of equal intervals asked for
  double path_tolerance = 1e-6;  ///< relative to the states' scale (path_error.hpp)
  int coarsest = 10;             ///< continuation starts at the first of N, N/4, N/16, … below 4 times this
  int max_rounds = 6;            ///< refinement rounds after the asked-for mesh
  int max_intervals = 20000;
  /// A guess starts at the asked-for mesh directly (it is the continuation's start), unless this
  /// is set (a perturbed start: carried to the coarse meshes first).
  bool continuation_from_guess = false;
  /// Called with each round's line ("round 2: 40 intervals, 12 iterations, cost …, path error …").
  std::function<void(const std::string&)> report;
};

struct Round {
  int intervals = 0;
  Solution solution;
  PathError error;
  bool measured = false;  ///< the path error was measured (not for a failed solve)
};

struct Outcome {
  enum class Status {
    optimal,     ///< IPOPT converged (or stopped at its acceptable level) and the path error meets the tolerance
    path_error,  ///< the path error stays above the tolerance: `words` names the interval
    solver,      ///< IPOPT did not converge on the last mesh (`solution.words`)
  } status = Status::solver;
  std::shared_ptr<HermiteSimpson> problem;  ///< the last mesh
  Solution solution;                        ///< its solve
  PathError error;  ///< its path error (measured unless status is solver and nothing was reached)
  bool measured = false;
  std::vector<Round> rounds;
  std::string words;  ///< why not optimal, in words
};

/// `start` bent by a seeded smooth perturbation: each state of each point moved by
/// sum_m a_m sin(m pi s) (m = 1, 2, 3; a_m uniform in +-amplitude max(1, the state's largest
/// |value|); s the point's fraction of the horizon), its rate by the derivative; clamped into
/// the bounds. The ends keep their values.
std::vector<double> perturbed_start(const HermiteSimpson& problem, const std::vector<double>& start, unsigned seed,
                                    double amplitude = 0.1);

/// Solves `problem`'s NLP from `guess` (on `problem`'s own mesh; empty: the straight line) by
/// continuation and refinement. `problem` carries the lowered functions; its mesh is replaced.
Outcome solve_refined(const HermiteSimpson& problem, const std::vector<double>& guess,
                      const SolveOptions& solve_options, const RefineOptions& options);

}  // namespace nhc::optimize
