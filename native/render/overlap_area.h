// Exact areas of overlap in the plane, for the coverage of a pixel by a light's image on the film
// (screen_lights.h): a convex polygon with a box, and the unit disk with a polygon.
#pragma once

namespace sphrect::render {

// Area of the convex polygon (x[i], y[i]), i < n <= 8, either orientation, inside the box
// [bx0, bx1] x [by0, by1] (Sutherland-Hodgman against the box's four sides, then the shoelace).
double ConvexPolygonBoxArea(const double* x, const double* y, int n, double bx0, double by0, double bx1, double by1);

// Signed area of the unit disk inside the polygon (x[i], y[i]) (positive counter-clockwise): the sum
// over its edges of the disk's part of the triangle (origin, edge), each a triangle and sectors.
double UnitDiskPolygonArea(const double* x, const double* y, int n);

}  // namespace sphrect::render
