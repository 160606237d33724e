#pragma once
// Placeholder content of the bridge until the Bullet bridge issue fills it:
// proves that the matching Bullet build links and answers.
#include "xpbd_bullet/precision_check.hpp"  // first: the float/double guard

namespace xpbd_bullet {

// Drops a unit sphere from y0 onto a static ground plane in a
// btDiscreteDynamicsWorld for `seconds`; returns the final height of its centre (m).
double drop_sphere_on_ground(double y0, double seconds);

// True if Bullet was built with the same scalar as xpbd::Real.
bool bullet_scalar_matches();

}  // namespace xpbd_bullet
