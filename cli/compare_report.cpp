// compare.md of nhc compare (compare_report.hpp).
#include "compare_report.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "nhc/base/number_text.hpp"

namespace nhc::cli {

namespace fs = std::filesystem;

namespace {

/// Below this a difference, drift or value is shown as "< 1e-12": rounding noise, which also
/// varies with the compiler, and would make the committed docs/compare.md flicker.
constexpr double kNoise = 1e-12;

std::string magnitude(double v) {
  if (std::isnan(v)) return "—";
  return v < kNoise ? (v == 0 ? "0" : "< 1e-12") : base::number_text(v, 4);
}

std::string value(double v) {
  if (std::isnan(v)) return "—";
  if (std::abs(v) < kNoise && v != 0) return "≈ 0";
  return base::number_text(v, 6);
}

/// Text for a Markdown table cell: a '|' would end the cell.
std::string cell(const std::string& text) {
  std::string s;
  for (char c : text) s += c == '|' ? std::string("\\|") : std::string(1, c);
  return s;
}

bool same_value(double a, double b) { return std::abs(a - b) <= 1e-9 * (1 + std::max(std::abs(a), std::abs(b))); }

bool is_observable(const std::string& column) {
  return column == "t" || column.rfind("hidden:", 0) == 0 || column.rfind("constraint:", 0) == 0 ||
         column.rfind("invariant:", 0) == 0 || column.rfind("error:", 0) == 0;
}

/// The given value of a CSV column "x''" from [initial] x = [x, x', x'', …], if given.
std::optional<double> given_value(const CompareSettings& settings, const std::string& column) {
  const auto prime = column.find('\'');
  const std::string base = column.substr(0, prime);
  const std::size_t order = prime == std::string::npos ? 0 : column.size() - prime;
  const auto it = settings.given.find(base);
  if (it == settings.given.end() || order >= it->second.size()) return std::nullopt;
  return it->second[order];
}

struct RanModel {
  const ComparedModel* model;
  CsvTable table;
};

void write_outcomes(std::ostream& md, const std::vector<ComparedModel>& models) {
  md << "## Outcome\n\n| model | outcome | IDA steps | data |\n|---|---|---|---|\n";
  for (const ComparedModel& m : models)
    if (!m.csv.empty())
      md << "| " << m.name << " | " << cell(m.outcome) << " | " << m.steps << " | [" << m.csv << "](" << m.csv
         << ") |\n";
  md << "\n";
  bool any = false;
  for (const ComparedModel& m : models)
    if (m.csv.empty()) {
      if (!any) md << "Models that do not apply, or stop at t0:\n\n";
      any = true;
      md << "- **" << m.name << "**: " << m.unavailable << "\n";
    }
  if (any) md << "\n";
}

/// Values of `column` at t0 grouped by model: "0.559 (vakonomic, chetaev), 0 (suslov)".
std::string grouped(const std::vector<RanModel>& ran, const std::string& column) {
  std::vector<std::pair<double, std::string>> groups;
  for (const RanModel& r : ran) {
    const int c = r.table.column(column);
    if (c < 0) continue;
    const double v = r.table.rows.front()[c];
    auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return same_value(g.first, v); });
    if (it == groups.end()) groups.emplace_back(v, r.model->name);
    else it->second += ", " + r.model->name;
  }
  std::string s;
  for (const auto& [v, names] : groups) s += (s.empty() ? "" : "; ") + value(v) + " (" + names + ")";
  return s;
}

void write_consistent_points(std::ostream& md, const CompareSettings& settings, const std::vector<RanModel>& ran) {
  std::vector<std::string> columns;
  for (const RanModel& r : ran)
    for (const std::string& c : r.table.header)
      if (!is_observable(c) && std::find(columns.begin(), columns.end(), c) == columns.end()) columns.push_back(c);
  // Grouped by variable (in order of first appearance), derivatives in order: x, x', x'', x'''.
  auto base_of = [](const std::string& c) { return c.substr(0, c.find('\'')); };
  std::vector<std::string> bases;
  for (const std::string& c : columns)
    if (std::find(bases.begin(), bases.end(), base_of(c)) == bases.end()) bases.push_back(base_of(c));
  auto key = [&](const std::string& c) {
    return std::make_pair(std::find(bases.begin(), bases.end(), base_of(c)) - bases.begin(), c.size());
  };
  std::stable_sort(columns.begin(), columns.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });

  md << "## Consistent initial points\n\n"
     << "Every model starts from the scene's [initial] values and completes them to a consistent point of "
        "its own equations: the given values of the differential states are kept, the rest (algebraic "
        "states, derivatives, multipliers) solved from the hidden constraints and the residuals "
        "(`nhc analyze` shows the equations). The first row of each CSV file, at t0 = "
     << value(settings.t0) << ":\n\n| quantity | given |";
  for (const RanModel& r : ran) md << ' ' << r.model->name << " |";
  md << "\n|---|---|";
  for (std::size_t k = 0; k < ran.size(); ++k) md << "---|";
  md << "\n";
  std::vector<std::string> notes;
  for (const std::string& column : columns) {
    const std::optional<double> given = given_value(settings, column);
    md << "| " << column << " | " << (given ? value(*given) : "") << " |";
    std::vector<double> values;
    std::vector<std::string> moved;
    for (const RanModel& r : ran) {
      const int c = r.table.column(column);
      if (c < 0) {
        md << " — |";
        continue;
      }
      const double v = r.table.rows.front()[c];
      values.push_back(v);
      if (given && !same_value(v, *given)) moved.push_back(r.model->name);
      md << ' ' << value(v) << " |";
    }
    md << "\n";
    const bool differ = std::any_of(values.begin(), values.end(), [&](double v) { return !same_value(v, values[0]); });
    if (differ) notes.push_back("**" + column + "** differs: " + grouped(ran, column) + ".");
    std::string list;
    for (const std::string& m : moved) list += (list.empty() ? "" : ", ") + m;
    if (!moved.empty())
      notes.push_back("**" + column + "** is given as " + value(*given) + " but moved by " + list +
                      " (the given values are not consistent with its equations).");
  }
  md << "\n";
  if (notes.empty()) md << "All models complete the given values to the same point.\n\n";
  else {
    md << "What differs:\n\n";
    for (const std::string& n : notes) md << "- " << n << "\n";
    md << "\n";
  }
}

void write_differences(std::ostream& md, const CompareSettings& settings, const std::vector<RanModel>& ran) {
  md << "## Differences between the motions\n\n"
     << "Per pair of models, the largest |q_a − q_b| of each coordinate over the output times both "
        "reached, and the first output time at which some coordinate differs by more than "
     << base::number_text(settings.tolerance, 3) << " (`--tolerance`).\n\n| models |";
  for (const std::string& q : settings.coordinates) md << " max Δ" << q << " |";
  md << " separate at t | compared up to t |\n|---|";
  for (std::size_t k = 0; k < settings.coordinates.size() + 2; ++k) md << "---|";
  md << "\n";
  for (std::size_t i = 0; i < ran.size(); ++i)
    for (std::size_t j = i + 1; j < ran.size(); ++j) {
      const PairDifference d = compare_motions(ran[i].table, ran[j].table, settings.coordinates, settings.tolerance);
      md << "| " << ran[i].model->name << " – " << ran[j].model->name << " |";
      for (double v : d.max_difference) md << ' ' << magnitude(v) << " |";
      md << ' ' << (d.separation < 0 ? std::string("never") : value(d.separation)) << " | " << value(d.compared_until)
         << " |\n";
    }
  if (ran.size() < 2) md << "\n(Only one model ran: nothing to compare.)\n";
  md << "\n";
}

/// max_t |column| or max_t |column − first|, over the rows.
double max_deviation(const CsvTable& table, int column, bool from_first) {
  double worst = 0;
  const double first = table.rows.front()[column];
  for (const auto& row : table.rows) {
    const double v = std::abs(row[column] - (from_first ? first : 0.0));
    worst = std::isnan(v) ? v : std::max(worst, v);
    if (std::isnan(worst)) break;
  }
  return worst;
}

void write_invariants(std::ostream& md, const std::vector<RanModel>& ran) {
  md << "## Invariants and hidden constraints\n\n"
     << "Per model: each invariant of the scene at t0 and its largest drift |I(t) − I(t0)|, and the largest "
        "residual of the model's hidden constraints |g_i| (— where the model has none), over its run. "
     << "The constraints f^α themselves are evaluated from the CSV columns: the models that solve them keep "
        "them to the integration tolerance; the suslov model only monitors them (models.md).\n\n"
     << "| model | quantity | at t0 | largest drift or residual |\n|---|---|---|---|\n";
  for (const RanModel& r : ran) {
    double hidden = -1;
    for (std::size_t c = 0; c < r.table.header.size(); ++c) {
      const std::string& name = r.table.header[c];
      if (name.rfind("invariant:", 0) == 0)
        md << "| " << r.model->name << " | " << name.substr(10) << " | " << value(r.table.rows.front()[c]) << " | "
           << magnitude(max_deviation(r.table, static_cast<int>(c), true)) << " |\n";
      if (name.rfind("hidden:", 0) == 0 || name.rfind("constraint:", 0) == 0)
        hidden = std::max(hidden, max_deviation(r.table, static_cast<int>(c), false));
    }
    md << "| " << r.model->name << " | hidden constraints | | " << (hidden < 0 ? "—" : magnitude(hidden)) << " |\n";
    for (const ConstraintCheck& f : r.model->constraints)
      md << "| " << r.model->name << " | constraint " << cell(f.name) << " | " << value(f.at_t0) << " | "
         << magnitude(f.largest) << " |\n";
  }
  md << "\n";
}

}  // namespace

PairDifference compare_motions(const CsvTable& a, const CsvTable& b, const std::vector<std::string>& coordinates,
                               double tolerance) {
  PairDifference d;
  d.max_difference.assign(coordinates.size(), 0.0);
  const int ta = a.column("t"), tb = b.column("t");
  for (std::size_t row = 0; row < a.rows.size() && row < b.rows.size(); ++row) {
    const double t = a.rows[row][ta];
    // A run that stops early ends with the point where it stopped, off the output grid.
    if (!same_value(t, b.rows[row][tb])) break;
    d.compared_until = t;
    bool apart = false;
    for (std::size_t k = 0; k < coordinates.size(); ++k) {
      const double delta = std::abs(a.rows[row][a.column(coordinates[k])] - b.rows[row][b.column(coordinates[k])]);
      d.max_difference[k] = std::isnan(delta) ? delta : std::max(d.max_difference[k], delta);
      apart = apart || !(delta <= tolerance);
    }
    if (apart && d.separation < 0) d.separation = t;
  }
  return d;
}

std::string compare_markdown(const fs::path& dir, const CompareSettings& settings,
                             const std::vector<ComparedModel>& models, const std::vector<Plot>& plots) {
  std::vector<RanModel> ran;
  for (const ComparedModel& m : models)
    if (!m.csv.empty()) ran.push_back({&m, read_csv_table(dir / m.csv)});

  std::ostringstream md;
  md << "# " << settings.scene_name << ": the models side by side\n\n"
     << "`" << settings.command_line << "`: every model from the same initial data, t from " << value(settings.t0)
     << " to " << value(settings.t_end) << " (" << settings.outputs << " output intervals), rtol "
     << base::number_text(settings.rtol, 3) << ", atol " << base::number_text(settings.atol, 3)
     << ". One CSV file per model (the columns of `nhc simulate -o`); the plots are drawn from them. "
        "Magnitudes below 1e-12 (rounding) are shown as < 1e-12, values as ≈ 0.\n\n";
  write_outcomes(md, models);
  write_consistent_points(md, settings, ran);
  write_differences(md, settings, ran);
  write_invariants(md, ran);
  md << "## Plots\n\nEach picture is also a PNG of the same name, drawn by its gnuplot script (`NAME.gp`).\n\n"
     << markdown_images(plots);
  md << "## Wall times\n\n";
  for (const ComparedModel& m : models)
    if (!m.csv.empty())
      md << "- " << m.name << ": derive, generate and compile " << base::number_text(m.build_seconds, 3)
         << " s, integrate " << base::number_text(m.integrate_seconds, 3) << " s\n";
  return md.str();
}

}  // namespace nhc::cli
