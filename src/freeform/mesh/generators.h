// Generated test and demo meshes at any resolution. All are consistently oriented
// (normals point +z for planar ones, outward for closed ones) and free of degenerate faces.
#pragma once

#include "freeform/mesh/types.h"

namespace freeform {

// Regular grid on [0,width] x [0,height] in z = 0, nx by ny quads, each split in two
// triangles along alternating diagonals. (nx+1)*(ny+1) vertices, row-major from (0,0).
TriangleSoup make_plane(int nx, int ny, double width = 1.0, double height = 1.0);

// Disk of the given radius in z = 0 centred at the origin: a centre vertex and `rings`
// concentric rings; ring r has 6r vertices (near-equilateral triangles).
TriangleSoup make_disk(int rings, double radius = 1.0);

// Annulus r_inner <= |x| <= r_outer in z = 0: `rings`+1 concentric circles of `segments`
// vertices each, radii spaced so triangles stay near-equilateral (geometric spacing).
TriangleSoup make_annulus(double r_inner, double r_outer, int rings, int segments);

// Icosahedron subdivided `subdivisions` times (each face into 4), projected to the sphere.
// 10*4^s+2 vertices.
TriangleSoup make_icosphere(int subdivisions, double radius = 1.0);

// Open cylinder of the given radius around the z axis, z in [0, height]: `rings`+1 circles of
// `segments` vertices; two boundary loops.
TriangleSoup make_cylinder(int rings, int segments, double radius = 1.0, double height = 1.0);

// make_plane with z = amplitude * sin(2 pi f x / width) * sin(2 pi f y / height).
TriangleSoup make_bumpy_plane(int nx, int ny, double amplitude, double frequency, double width = 1.0,
                              double height = 1.0);

// Each triangle into four through its edge midpoints (positions not smoothed): large meshes
// from real ones (benchmarks, the accuracy tests). 4x the faces.
TriangleSoup subdivide_midpoint(const TriangleSoup& in);

}  // namespace freeform
