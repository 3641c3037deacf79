// The container walls as polygons at the current container scale, for pictures
// (docs/output-format.md, "VTK files", container_<tag>.vtp). The walls themselves are
// infinite half-spaces (scene/scene.hpp, WallDef); this is a finite drawing of them.
// A pure function of the scene and s_c.
#pragma once

#include <vector>

#include "ratchet/scene/scene.hpp"

namespace ratchet {

struct ContainerMesh {
  std::vector<Vec3> points;
  // Indices into points. Counter-clockwise seen from the side the wall's normal points
  // to: the right-hand normal of each polygon is its wall's normal (into the container).
  std::vector<std::vector<int>> polygons;
  std::vector<int> wall;  // per polygon: its wall (index into scene.container.walls)
};

// The mesh at container scale 1, then every point of a wall that expands moved to
// c0 + s_c (p - c0) about the container's scale centre c0, as the wall points move
// (World::wall_point); points of walls that do not expand stay.
//  - Cone of N segments, bottom apothem r_c, opening angle theta, height H: the corners
//    of the bottom N-gon at z = 0 lie at azimuth (2j - 1) pi / N and distance
//    r_c / cos(pi / N), those of the top N-gon at z = H at distance
//    (r_c + H tan theta) / cos(pi / N). Polygon 0 is the floor (wall 0, the bottom
//    N-gon); polygon k + 1 is side segment k (wall k + 1), the quadrilateral between
//    corners k and k + 1 of both N-gons. Every corner lies on the planes of its walls.
//  - Planes: one square per plane (wall i, polygon i) centred at the plane's point,
//    of half side plane_patch_half_side(scene, i), edges along u and v = n x u, u the
//    unit vector n x e normalised, e the coordinate axis least aligned with n.
//  - No container: an empty mesh.
ContainerMesh container_mesh(const SceneDef& scene, double s_c);

// Half side (at scale 1) of the square drawn for wall `wall` of a planes container:
// twice the largest distance from the plane's point to any point of a body's bounding
// sphere at its initial position, 2 max_i (|x_i(0) - p| + R_i), so that the square
// covers the initial bed seen along the normal with room to spare. 0 without bodies.
double plane_patch_half_side(const SceneDef& scene, int wall);

}  // namespace ratchet
