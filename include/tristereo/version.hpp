#pragma once

namespace tristereo {
constexpr const char* kVersionString = "0.1.0";
}  // namespace tristereo
