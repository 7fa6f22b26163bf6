// TRISTEREO_API marks the public API. The library is compiled with hidden
// visibility, so a shared build (BUILD_SHARED_LIBS=ON) exports exactly what
// carries this mark; in a static build it changes nothing. On ELF the same
// attribute serves the library and its users.
#pragma once

#if defined(__GNUC__) || defined(__clang__)
#define TRISTEREO_API __attribute__((visibility("default")))
#else
#define TRISTEREO_API
#endif
