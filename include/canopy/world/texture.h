#pragma once
// Textures of imported plants: decoding image files (TGA, PNG, JPEG, BMP through stb_image),
// how much of a texture a mesh's faces cover (texture coordinates per face corner), and the
// mean colour of what they cover. Free of MuJoCo and of any segmentation.

#include <array>
#include <string>
#include <vector>

#include "canopy/common/image.h"
#include "canopy/common/types.h"

namespace canopy::world {

/// Texture coordinates of a face's three corners: (u, v) with v = 0 at the image's bottom
/// row (the convention of OBJ, COLLADA and assimp); values outside [0, 1] repeat.
using FaceUv = std::array<Vec2, 3>;

/// Largest texture side accepted [px] (a header claiming more is an error, read before any
/// pixel memory is allocated).
constexpr int kMaxTextureSidePx = 8192;

/// Decodes an image file's bytes (TGA, PNG, JPEG, BMP, ...) to 8-bit RGB; alpha is dropped.
/// Throws InputError naming `what` when the bytes are no image stb_image reads, too large, or
/// a TGA whose pixel data end before its header's size (stb_image would fill the rest black).
Image<Rgb8> decode_image(const std::string& bytes, const std::string& what);

/// Weight of every texel (row-major, row 0 at the image's top) in the area the faces cover
/// in texture space: a texel counts once per face whose UV triangle holds its centre (UVs
/// wrap); a face holding no texel centre adds its UV area to the texel under its centroid.
/// Faces spanning more than kMaxTexelsPerFace texels are sampled on a grid of that many
/// points, weighted by their area. The sum is the covered area in texels.
std::vector<double> texel_weights(int width, int height, const std::vector<FaceUv>& uv);
constexpr long kMaxTexelsPerFace = 1 << 20;

/// Weighted mean colour (0..1) of `image` under `weights` (all texels alike when the weights
/// sum to zero).
std::array<float, 3> mean_color(const Image<Rgb8>& image, const std::vector<double>& weights);

}  // namespace canopy::world
