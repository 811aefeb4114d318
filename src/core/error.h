/// @file error.h
/// @brief The exception hierarchy of cavesim: defined in the public header include/cavesim/error.h,
/// which the library's users catch too.
#pragma once

#include "cavesim/error.h"
