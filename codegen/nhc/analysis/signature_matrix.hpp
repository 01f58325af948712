#pragma once
/// \file signature_matrix.hpp
/// \brief Pryce's signature matrix σ_ij = highest order of x_j in f_i, −∞ when x_j is absent
/// (models.md, "Structural analysis", step 1; Pryce, BIT 41 (2001) 364–394, §2).
///
/// x_j^(k) counts as present in f_i only when ∂f_i/∂x_j^(k) is not identically zero after
/// GiNaC's normal(): a symbol that occurs but cancels does not raise σ.

#include <ginac/ginac.h>

#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "nhc/analysis/dae_system.hpp"
#include "nhc/jet/jet_space.hpp"

namespace nhc {

class SignatureMatrix {
 public:
  /// σ_ij = −∞.
  static constexpr int kAbsent = std::numeric_limits<int>::min();

  SignatureMatrix() = default;
  SignatureMatrix(int rows, int cols)
      : rows_(rows), cols_(cols), entries_(static_cast<std::size_t>(rows * cols), kAbsent) {}

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  int operator()(int i, int j) const { return entries_[index(i, j)]; }
  int& operator()(int i, int j) { return entries_[index(i, j)]; }
  bool present(int i, int j) const { return (*this)(i, j) != kAbsent; }

 private:
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(i * cols_ + j); }
  int rows_ = 0;
  int cols_ = 0;
  std::vector<int> entries_;
};

/// Highest k with ∂f/∂x^(k) ≢ 0 for the variable (kind, index), or kAbsent.
int signature_entry(const GiNaC::ex& f, const JetSpace& jet, VariableKind kind, int index);

/// σ of a DAE: rows are its equations, columns its unknowns.
SignatureMatrix signature_matrix(const DaeSystem& system);

/// Column j of each unknown x_j, keyed by its (kind, index).
std::map<std::pair<VariableKind, int>, int> unknown_columns(const DaeSystem& system);

}  // namespace nhc
