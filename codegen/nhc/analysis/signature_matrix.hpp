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
#include "nhc/expr/jet_space.hpp"

namespace nhc {

class SignatureMatrix {
 public:
  /// σ_ij = −∞.
  static constexpr int kAbsent = std::numeric_limits<int>::min();
  /// A finite entry σ_{i,col} of one row.
  struct Entry {
    int col = 0;
    int value = 0;
  };

  SignatureMatrix() = default;
  /// All entries −∞. Stored by rows, only the finite entries (sorted by column): a chain of N
  /// bodies has O(N) of them, and nothing in the Σ-method needs the N² absent ones, so the work stays linear in N.
  SignatureMatrix(int rows, int cols) : cols_(cols), rows_(static_cast<std::size_t>(rows)) {}

  int rows() const { return static_cast<int>(rows_.size()); }
  int cols() const { return cols_; }
  /// σ_ij, or kAbsent; O(log of the row's entries).
  int operator()(int i, int j) const;
  bool present(int i, int j) const { return (*this)(i, j) != kAbsent; }
  /// σ_ij = value; kAbsent removes the entry.
  void set(int i, int j, int value);
  /// The finite entries of row i, by increasing column.
  const std::vector<Entry>& row(int i) const { return rows_.at(static_cast<std::size_t>(i)); }

 private:
  int cols_ = 0;
  std::vector<std::vector<Entry>> rows_;
};

/// Highest k with ∂f/∂x^(k) ≢ 0 for the variable (kind, index), or kAbsent.
int signature_entry(const GiNaC::ex& f, const JetSpace& jet, VariableKind kind, int index);

/// σ of a DAE: rows are its equations, columns its unknowns.
SignatureMatrix signature_matrix(const DaeSystem& system);

/// Column j of each unknown x_j, keyed by its (kind, index).
std::map<std::pair<VariableKind, int>, int> unknown_columns(const DaeSystem& system);

}  // namespace nhc
