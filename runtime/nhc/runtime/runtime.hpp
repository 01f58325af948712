#pragma once
/// \file runtime.hpp
/// \brief The nhc runtime: integrates generated models (docs/generated-code.md) with SUNDIALS IDA.
#include "nhc/base/errors.hpp"
#include "nhc/runtime/hidden_constraints.hpp"
#include "nhc/runtime/integrator.hpp"
#include "nhc/runtime/model.hpp"
#include "nhc/runtime/model_table.h"
#include "nhc/runtime/sensitivity.hpp"
#include "nhc/runtime/trajectory.hpp"
#include "nhc/runtime/variational.hpp"
#include "nhc/runtime/work_precision.hpp"
