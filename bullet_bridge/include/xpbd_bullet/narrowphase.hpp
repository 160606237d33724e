#pragma once
// Contact queries of particles against Bullet rigid shapes (docs/design.md section 4).
//
// A particle is treated as a point (its centre); callers add the particle
// radius to the speculative margin and subtract it from the distance. Every
// query works in world space: the collision object's world transform (and a
// compound child's transform) is applied here.
//
// Which code answers which shape (details and measured FCL behaviour in
// docs/collision-queries.md):
//   sphere, box, capsule X/Y/Z, cylinder X/Y/Z, static plane: own closed forms
//   any other btConvexShape (hull, cone, ...):   btGjkEpaSolver2 (GJK outside, EPA inside)
//   btCompoundShape:                             recursion, smallest distance wins
//   any btConcaveShape with triangles (BVH mesh, scaled BVH mesh, heightfield,
//   plain triangle mesh): processAllTriangles + own one-sided closest point
//
// Surfaces: a box, capsule, cylinder or sphere is its nominal geometry (the
// dimensions given to Bullet, local scaling applied; Bullet keeps their margin
// inside). A generic convex shape includes its collision margin, as Bullet's
// own GJK sees it: a hull with margin m is the hull grown by m (rounded).
// Triangle meshes are one-sided: the front of a triangle is the side its
// counter-clockwise winding faces (normal (v1-v0)x(v2-v0)); a heightfield's
// front is always its up-axis side.
//
// None of the queries allocates memory, and all are safe to call concurrently
// on objects that are not being modified.
#include "xpbd_bullet/precision_check.hpp"  // first: the float/double guard

#include <vector>

#include "xpbd/types.hpp"

class btCollisionObject;
class btCollisionShape;
class btCollisionWorld;

namespace xpbd_bullet {

// The closest feature of a rigid shape to a particle centre x. Always
// x == point + distance * normal (up to round-off) for query_point.
struct ParticleContact {
  xpbd::Vec3 point = xpbd::Vec3::Zero();   // m, world point on the rigid surface
  xpbd::Vec3 normal = xpbd::Vec3::Zero();  // unit, world, from the surface towards the particle (outward)
  xpbd::Real distance = 0;                 // m, signed distance of the centre along normal (negative = inside)
};

// True if query_point / sweep_point can answer for this shape (see the table
// above). Unsupported shapes (e.g. a soft body's shape, btEmptyShape) never
// produce contacts and are skipped by candidates().
bool is_supported(const btCollisionShape& shape);

// Signed distance of the point x (m, world) from the surface of obj's shape.
// Returns false, leaving out unchanged, if the point is farther than
// max_distance (m, >= 0, the speculative margin) outside the surface.
// Points inside a closed shape are always reported (distance < 0, normal
// towards the nearest face). Triangle meshes are thin shells: a point behind
// a triangle is reported as penetrating only if it is within max_distance of
// it (the same search radius in front and behind).
// Throws std::invalid_argument (naming the argument and its value) if x is not
// finite or max_distance is negative or not finite.
bool query_point(const btCollisionObject& obj, const xpbd::Vec3& x, xpbd::Real max_distance,
                 ParticleContact& out);

// Objects of world whose broadphase AABB overlaps the box [lo, hi] (m, world;
// e.g. a soft body's AABB swept over the step and grown by the margin), from
// the world's broadphase (aabbTest) followed by an exact AABB overlap test.
// Skips soft bodies, ghost objects, objects without contact response
// (CF_NO_CONTACT_RESPONSE), unsupported shapes, and objects rejected by the
// Bullet collision filter (group & proxy mask, proxy group & mask).
// out is cleared first; it allocates only when it must grow past its capacity.
// Throws std::invalid_argument if lo/hi are not finite or lo > hi on an axis.
void candidates(btCollisionWorld& world, const xpbd::Vec3& lo, const xpbd::Vec3& hi,
                std::vector<const btCollisionObject*>& out, int filter_group = 1, int filter_mask = -1);

// First hit of the point moving on the segment a -> b (m, world) with obj's
// surface, for tunnelling prevention. On a hit: fraction in [0, 1] with
// a + fraction (b - a) on the surface, out.point = that surface point,
// out.normal = outward surface normal there, and out.distance = signed
// distance of the end point b from the tangent plane at the hit,
// (b - out.point) . out.normal (<= 0 when b passed through).
// A segment that starts inside a closed shape hits at fraction 0 with the
// contact of query_point(a). Triangle meshes are hit only on their front
// side (a segment leaving through a back face is no hit).
// Throws std::invalid_argument if a or b is not finite.
bool sweep_point(const btCollisionObject& obj, const xpbd::Vec3& a, const xpbd::Vec3& b,
                 ParticleContact& out, xpbd::Real& fraction);

}  // namespace xpbd_bullet
