// The simulator uses the project's one term catalog (algorithms/common/catalog.h).
#pragma once

#include "algorithms/common/catalog.h"

namespace fogpipe::simulation {

using catalog::AllTerms;
using catalog::KindOf;
using catalog::NeedsTemperature;
using catalog::ParseTerm;
using catalog::Term;
using catalog::TermKind;
using catalog::ToString;

}  // namespace fogpipe::simulation
