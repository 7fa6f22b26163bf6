// Internal: the KernelSet behind a (resolved) KernelChoice.
#pragma once

#include "src/kernels/kernel_set.hpp"
#include "tristereo/kernels.hpp"

namespace tristereo {

// Resolves `requested` (see resolve_kernel_choice) and returns its table.
// Throws Error(kInvalidArgument) when that set cannot run here.
const KernelSet& kernel_set_for(KernelChoice requested);

}  // namespace tristereo
