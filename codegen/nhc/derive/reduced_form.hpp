#pragma once
/// \file reduced_form.hpp
/// \brief The multiplier-free form of a model on independent speeds (Maggi's equations):
/// M_r(q, u, t) u' = f_r(q, u, t), with the dependent speeds and the multipliers recovered from
/// the same quantities (docs/reduced-form.md).
///
/// For constraints linear in the velocities, A(q, t) q' + b(q, t) = 0 (a holonomic f(q, t) = 0
/// enters as D f), the independent speeds u = q_I' and the dependent ones
///     q_D' = X u + y,  A_D [X y] = −[A_I b]                       (the null-space basis C = [I; X])
/// and R = K q'' + r + B^T λ (K = ∂R/∂q''), projected on C (Maggi 1896; Neimark & Fufaev 1972,
/// ch. III §2):
///     M_r = −C^T K C,   f_r = C^T (K w + R|_{λ=0} − K q''),   w = [0; w_D],  A_D w_D = −h,
///     h = D(A q' + b) − A q''   (the constraint's acceleration terms without q'').
/// f_r does not depend on q'' (R|_{λ=0} − K q'' is r, formed first so that R's terms in q''
/// cancel; q'' inside a named intermediate stays); everything is evaluated with q_D' = X u + y. Entries stay over the
/// scene's named intermediates; A_D's entries, X, y and w_D become intermediates where they are not small.

#include <ginac/ginac.h>

#include <optional>
#include <string>
#include <vector>

#include "nhc/derive/models.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

struct ReducedForm {
  bool available = false;
  std::string reason;                         ///< why not, in words, when !available
  std::vector<int> independent;               ///< coordinate indices I (speeds u = q_I')
  std::vector<int> dependent;                 ///< coordinate indices D
  std::vector<std::string> speeds;            ///< "phi'", … (primed names of I)
  std::string rule;                           ///< how the speeds were chosen, in words
  std::vector<std::string> dependent_names;   ///< "x'", … (primed names of D)
  std::vector<GiNaC::ex> dependent_symbols;   ///< the jet symbols q_D'
  std::vector<GiNaC::ex> dependent_speeds;    ///< q_D' = X u + y, per D
  GiNaC::matrix mass_matrix;                  ///< M_r, |I| × |I|
  std::vector<GiNaC::ex> forcing;             ///< f_r, |I|
  std::vector<std::string> multiplier_names;  ///< "lambda1" (chetaev), "lambda1'" (holder)
  std::vector<GiNaC::ex> multipliers;         ///< λ of q, u, u' (u' = q_I''), per constraint
  /// Every expression above, for the "where" list of the printers.
  std::vector<GiNaC::ex> expressions() const;
};

/// The reduced form of `model` on the speeds named in `speeds` ("phi'", …; empty: the default
/// rule, docs/reduced-form.md: the scene's `dependent` key, else the first coordinates whose
/// constraint columns are independent at the scene's initial point). A bad speed list throws
/// InputError naming `flag`; a model without the form returns !available with the reason.
ReducedForm reduce_to_independent_speeds(const Scene& scene, const DerivedModel& model,
                                         const std::vector<std::string>& speeds = {},
                                         const std::string& flag = "--speeds");

/// The coordinates whose speeds the default rule (above) makes dependent, in increasing order: the
/// scene's `dependent` key, else chosen at the initial point; nullopt when the rule cannot choose
/// (a constraint not of order 0 or 1 or not linear in the velocities, df/dq' without a value or of
/// rank below g there). The multiplier-free form built without named speeds depends on the initial
/// point only through this (the scene cache keys the generated header with it, jit/build.cpp).
std::optional<std::vector<int>> default_dependent_coordinates(const Scene& scene);

/// "phi',delta', thr'" → {"phi'", "delta'", "thr'"} (commas, spaces around each name).
std::vector<std::string> parse_speed_list(const std::string& text);

}  // namespace nhc
