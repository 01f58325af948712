#pragma once
/// \file ensemble.hpp
/// \brief nhc::ensemble — many runs of one compiled model (docs/ensemble.md): the design
/// (grid or random sample), one run and its record, dynamic load balancing over threads and MPI
/// ranks, the HDF5 results file, maps of an outcome. Used by `nhc ensemble` and `nhc plot`.

#include "nhc/ensemble/design.hpp"
#include "nhc/ensemble/plot.hpp"
#include "nhc/ensemble/results_file.hpp"
#include "nhc/ensemble/run.hpp"
#include "nhc/ensemble/scheduler.hpp"
#include "nhc/ensemble/session.hpp"
