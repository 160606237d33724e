#pragma once
// Compile-time check that this file sees Bullet with the precision the
// xpbd_bullet library was built with (xpbd/config.hpp, XPBD_DOUBLE).
//
// Debian's double Bullet (bullet-float64) and its float Bullet (bullet) have
// the same headers, and btScalar is double only where BT_USE_DOUBLE_PRECISION
// is defined. A file compiled with the other precision than the library would
// otherwise link (the classes have the same names in both) and then fail at
// run time in misleading ways (for instance XpbdWorld::attach saying "body is
// not in the world"). Every public header of the bridge includes this one
// before anything else.
//
// The installed CMake package does not add BT_USE_DOUBLE_PRECISION to its
// consumers (neither does Bullet's own CMake config): a consumer of the
// float64 component defines it itself (docs/embedding.md). The pkg-config
// file xpbd_bullet-float64.pc gets it from bullet-float64.pc.
#include "xpbd/config.hpp"

#if XPBD_DOUBLE && !defined(BT_USE_DOUBLE_PRECISION)
#error "xpbd_bullet: this is the double-precision (float64) package but this file is compiled for float Bullet. Either use find_package(xpbd_bullet CONFIG REQUIRED COMPONENTS float) (a float build: -DXPBD_DOUBLE=OFF), or compile with BT_USE_DOUBLE_PRECISION and link bullet-float64."
#elif !XPBD_DOUBLE && defined(BT_USE_DOUBLE_PRECISION)
#error "xpbd_bullet: this is the float package but this file is compiled for double Bullet (BT_USE_DOUBLE_PRECISION is defined). Either use find_package(xpbd_bullet CONFIG REQUIRED COMPONENTS float64) (a double build: -DXPBD_DOUBLE=ON, the default), or compile without BT_USE_DOUBLE_PRECISION and link bullet."
#endif
