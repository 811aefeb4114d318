/// @file site.h
/// @brief Real site inputs: a DEM (GeoTIFF) as the land surface, sinkholes and springs from CSV,
/// geological surfaces (GeoTIFF grids or XYZ points), all in one projected CRS in metres, placed
/// on the block by `[site] origin` and the voxel size (docs/scenario-format.md, `[site]`).
///
/// Not in the paper, which types every feature in voxel units. World space here is the CRS's
/// (easting, northing, elevation) in metres; index space is the block's voxels: voxel (i, j, k)
/// spans origin + [i, i+1] · h in x (likewise y, z), its column centre at origin + (i + ½, j + ½) · h.
#pragma once

#include <string>

#include "sim/scenario.h"

namespace cavesim::site {

/// Whether the scenario names any site file.
bool hasSiteFiles(const Scenario& scenario);

/// Reads the files of `scenario.site` and `scenario.siteHorizons` and fills `scenario.siteData`:
/// each surface sampled at every column centre (GeoTIFF: bilinear between pixel centres; XYZ:
/// inverse-distance weighting, power 2, of the 8 nearest points, ties by file order), sinkholes
/// as sources and springs as sinks (one voxel each; a row without z in the highest voxel of its
/// column whose centre is not above the land surface). Relative paths are taken from the scenario
/// file's folder and replaced by absolute ones, so the effective scenario finds the files again.
/// Does nothing when the scenario names no site file.
/// @throw InputError naming the file (and line) and the value for: a missing file; a DEM or
///   `.tif`/`.tiff` surface that is not a GeoTIFF; a raster without a CRS, with a geographic CRS
///   (degrees) or a projected one not in metres; rasters whose CRSs differ; a surface that does not
///   cover every column, has no data there, or leaves the block's elevations; a point outside the
///   block or above the land surface; a malformed CSV or XYZ file; a sinkhole on a spring's voxel;
///   this build has no GDAL
void loadSite(Scenario& scenario);

/// Whether this build reads site files (was built with GDAL).
bool gdalAvailable();

}  // namespace cavesim::site
