#pragma once
/// \file output_selection.hpp
/// \brief The output times and CSV columns of a run, from their home in app/
/// (nhc/app/output_selection.hpp).

#include "nhc/app/output_selection.hpp"

namespace nhc::cli {

using app::csv_columns;
using app::parse_columns;
using app::parse_output_times;
using app::write_selected_csv;
using app::ExtraColumns;

}  // namespace nhc::cli
