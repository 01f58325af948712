// The hand-written Appell–Hamel model as a loadable shared object (what `nhc simulate` compiles).
#define NHC_EXPORT_MODEL_TABLE
#include "handwritten/appell_hamel_chetaev.hpp"
