// XpbdWorld::debugDraw: the systems through Bullet's debug drawer.
#include <LinearMath/btIDebugDraw.h>

#include "world_impl.hpp"
#include "xpbd/constraints.hpp"

namespace xpbd_bullet {

void XpbdWorld::debugDraw(btIDebugDraw* drawer) {
  if (drawer == nullptr) return;
  const int mode = drawer->getDebugMode();
  const bool wire = (mode & btIDebugDraw::DBG_DrawWireframe) != 0;
  const bool points = (mode & btIDebugDraw::DBG_DrawContactPoints) != 0;
  if (!wire && !points) return;
  const btIDebugDraw::DefaultColors colours = drawer->getDefaultColors();
  for (const auto& sp : systems_) {
    const System& s = *sp;
    const xpbd::Model& m = *s.model;
    const xpbd::State& st = s.state;
    if (wire) {
      // A system whose step failed is drawn in the colour Bullet uses for
      // bodies that are not simulated.
      const btVector3 colour =
          s.error.empty() ? colours.m_activeObject : colours.m_disabledSimulationObject;
      const auto& edges = m.get<xpbd::Distance>();
      if (!edges.empty()) {
        for (const xpbd::Distance& d : edges)
          drawer->drawLine(to_bt(st.x[d.p[0]]), to_bt(st.x[d.p[1]]), colour);
      } else {
        for (const auto& t : m.collision_triangles)
          for (int k = 0; k < 3; ++k)
            drawer->drawLine(to_bt(st.x[t[k]]), to_bt(st.x[t[(k + 1) % 3]]), colour);
      }
    }
    if (points) {
      // The particle-body contacts of the system's last step, at the body
      // poses XPBD ended that step with: the point on the body, its normal,
      // and the particle's signed distance from it along the normal.
      for (const xpbd::BodyContact& c : st.contacts) {
        Vec3 p = c.r, n = c.n;
        if (c.body >= 0) {
          const xpbd::RigidBody& b = st.bodies[std::size_t(c.body)];
          p = b.x + b.q * c.r;
          n = b.q * c.n;
        }
        drawer->drawContactPoint(to_bt(p), to_bt(n), btScalar(n.dot(st.x[c.particle] - p)), 0,
                                 colours.m_contactPoint);
      }
    }
  }
}

}  // namespace xpbd_bullet
