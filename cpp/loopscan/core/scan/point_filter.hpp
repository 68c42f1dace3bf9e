#pragma once
// De-duplicating filters applied to the imitated scan (camera frame, points within range).
#include "loopscan/core/types.hpp"

namespace loopscan {

// Cartesian voxel grid (origin (-r,-r,-r), voxel r/nx x r/ny x r/nz): keeps the HIGHEST point
// (smallest y: y points down) of each voxel, the first one on ties.
// Reference mode: the authors' double-precision filter and output order (libstdc++
// unordered_map iteration). Default mode: the single-precision path of camera_points.hpp (the
// one `describe` uses), voxels in order of first occurrence.
Cloud cartesian_filter(const Cloud& in, double range_m, int divisions_xz, int divisions_y,
                       Mode mode);

// Polar cells of `resolution_deg` in azimuth atan2(z, x) and elevation atan2(y, hypot(x, z)):
// keeps the point CLOSEST to the camera in each cell. Same ordering rule as above.
Cloud polar_filter(const Cloud& in, double resolution_deg, Mode mode);

}  // namespace loopscan
