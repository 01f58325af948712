#pragma once
/// \file output_selection.hpp
/// \brief What `nhc simulate` writes: the output times (`--outputs N`, `[simulate] outputs = N`,
/// `--output-times a:h:b` or `t1,t2,…`) and the CSV columns (`--columns x,y`; t always first;
/// the scene's [outputs] after the model's columns).
/// Bad specifications are bad input naming the flag (exit 2), checked before the run.

#include <iosfwd>
#include <string>
#include <vector>

#include "nhc/runtime/runtime.hpp"
#include "nhc/app/scene_outputs.hpp"

namespace nhc::app {

/// "a:h:b" (a, a + h, …, b; (b − a)/h must be a whole number to 1e-9) or "t1,t2,…" (increasing).
/// Their place against t0 (all at or after it, the last after it) is check_run_request's, with
/// the scene the run takes: a t0 written through a parameter moves with --set.
std::vector<double> parse_output_times(const std::string& spec);

/// The columns of the CSV runtime::write_csv writes for `model` (its header line, split), then
/// the scene's [outputs].
/// Columns after the [outputs] with one row of values per sample (a sampled controller's states).
struct ExtraColumns {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
};

std::vector<std::string> csv_columns(const runtime::Model& model, const std::vector<double>& p,
                                     const SceneOutputs& outputs, const ExtraColumns* extra = nullptr);

/// "x,y,lambda1" → the names, each checked against `available` (InputError naming --columns);
/// a name given twice is refused. "t" is kept in the list: `--columns t` selects t alone.
std::vector<std::string> parse_columns(const std::string& spec, const std::vector<std::string>& available);

/// runtime::write_csv with the [outputs] columns appended, restricted to t and `columns` in that
/// order (all when `columns` is empty; t is always first, once).
void write_selected_csv(std::ostream& out, const runtime::Model& model, const std::vector<double>& p,
                        const std::vector<runtime::Sample>& samples, const std::vector<std::string>& columns,
                        const SceneOutputs& outputs, const ExtraColumns* extra = nullptr);

}  // namespace nhc::app
