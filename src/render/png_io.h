/// @file png_io.h
/// @brief PNG input and output of RGB images through libpng.
#pragma once

#include <string>

#include "render/image.h"

namespace cavesim::render {

/// Writes `img` as an 8-bit RGB PNG.
/// @throw RuntimeError if the image is empty or the file cannot be written
void writePng(const std::string& path, const Image& img);

/// Reads a PNG (any bit depth / colour type is converted to 8-bit RGB; alpha is dropped).
/// @throw RuntimeError if the file is missing or not a valid PNG
Image readPng(const std::string& path);

}  // namespace cavesim::render
