#include "nhc/optimize/path_table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "nhc/io/printable.hpp"

namespace nhc::optimize {

namespace {

/// Per state, the name of its rate column, or "" when there is none (an algebraic state, or a
/// rate that is itself a state: x' of x when the states hold x and x').
std::vector<std::string> rate_names(const PointProblem& p) {
  std::vector<std::string> out;
  for (int i = 0; i < p.states; ++i) {
    const std::string rate = p.state_names[static_cast<std::size_t>(i)] + "'";
    const bool is_state = std::find(p.state_names.begin(), p.state_names.end(), rate) != p.state_names.end();
    out.push_back(p.collocated[static_cast<std::size_t>(i)] && !is_state ? rate : "");
  }
  return out;
}

}  // namespace

std::vector<std::string> path_columns(const HermiteSimpson& problem) {
  const PointProblem& p = problem.point_problem();
  const std::vector<std::string> rates = rate_names(p);
  std::vector<std::string> out{"t"};
  for (int i = 0; i < p.states; ++i) {
    out.push_back(p.state_names[static_cast<std::size_t>(i)]);
    if (!rates[static_cast<std::size_t>(i)].empty()) out.push_back(rates[static_cast<std::size_t>(i)]);
  }
  for (const std::string& u : p.input_names) out.push_back(u);
  return out;
}

std::vector<std::vector<double>> path_rows(const HermiteSimpson& problem, const std::vector<double>& z) {
  const PointProblem& p = problem.point_problem();
  const std::vector<std::string> rates = rate_names(p);
  std::vector<std::vector<double>> out;
  for (int j = 0; j < problem.points(); ++j) {
    std::vector<double> row{problem.time(j, z.data())};
    for (int i = 0; i < p.states; ++i) {
      row.push_back(z[static_cast<std::size_t>(problem.q_index(j, i))]);
      if (!rates[static_cast<std::size_t>(i)].empty())
        row.push_back(z[static_cast<std::size_t>(problem.v_index(j, i))]);
    }
    for (int k = 0; k < p.inputs; ++k) row.push_back(z[static_cast<std::size_t>(problem.u_index(j, k))]);
    out.push_back(std::move(row));
  }
  return out;
}

std::vector<double> guess_from_table(const HermiteSimpson& problem, const std::vector<std::string>& header,
                                     const std::vector<std::vector<double>>& rows, const Scene& scene,
                                     const std::string& where, const std::string& file) {
  const SourceLocation at{where, 0, 0};
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  };
  const std::string name = printable(file);
  if (rows.empty()) throw InputError(at, name + " has no rows");
  // Python hands rows of its own: each as wide as the header, every value finite (row r of the
  // table is line r + 2 of a file, after the header).
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (rows[r].size() != header.size())
      throw InputError(
          at, fmt::format("{}: row {} has {} values, the header {} names", name, r + 1, rows[r].size(), header.size()));
    for (std::size_t c = 0; c < header.size(); ++c)
      if (!std::isfinite(rows[r][c]))
        throw InputError(at, fmt::format("{}: row {}, column {} ('{}') is {}, not a finite number", name, r + 1, c + 1,
                                         printable(header[c]), rows[r][c]));
  }
  const int t = column("t");
  if (t < 0) throw InputError(at, name + " has no column t");
  for (std::size_t r = 1; r < rows.size(); ++r)
    if (!(rows[r][static_cast<std::size_t>(t)] >= rows[r - 1][static_cast<std::size_t>(t)]))
      throw InputError(at, fmt::format("{}: t does not increase at row {}", name, r + 1));
  for (const std::string& name : scene.jet->coordinates())
    if (column(name) < 0) throw InputError(at, printable(file) + " has no column " + name);
  const PointProblem& p = problem.point_problem();
  std::vector<int> q, v, u;
  for (int i = 0; i < p.states; ++i) {
    const std::string& name = p.state_names[static_cast<std::size_t>(i)];
    q.push_back(column(name));
    v.push_back(p.collocated[static_cast<std::size_t>(i)] ? column(name + "'") : -1);
  }
  // nhc simulate names an input's column input:NAME.
  for (const std::string& name : p.input_names) u.push_back(column(name) >= 0 ? column(name) : column("input:" + name));
  return problem.from_samples(rows, t, q, v, u);
}

}  // namespace nhc::optimize
