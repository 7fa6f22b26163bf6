// Float reference of the tritree mesher (docs/model.md section 1).
//
// A plain transcription of the model, independent of src/tritree: triangles
// in a std::vector, neighbours found through a map from edges to leaves,
// pixel ownership tested pixel by pixel, plane residuals in double with Eigen.
// Its output must equal tristereo::Tritree::build() exactly (Mesh::operator==).
#pragma once

#include "tristereo/image.hpp"
#include "tristereo/mesh.hpp"
#include "tristereo/params.hpp"

namespace tristereo::reference {

// Meshes `gray` (1 channel, W, H in 2..kMaxImageSide). Throws Error on a bad
// image or parameters outside the ranges of params.hpp.
Mesh build_tritree(const ImageU8& gray, const TritreeParams& params);

}  // namespace tristereo::reference
