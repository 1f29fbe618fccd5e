#include "algorithms/common/status.h"

namespace fogpipe {

const char* ToString(Termination termination) {
  switch (termination) {
    case Termination::kSuccess:
      return "success";
    case Termination::kNoConvergence:
      return "no_convergence";
    case Termination::kInvalidOptions:
      return "invalid_options";
    case Termination::kInsufficientData:
      return "insufficient_data";
    case Termination::kNumericalFailure:
      return "numerical_failure";
  }
  return "unknown";
}

}  // namespace fogpipe
