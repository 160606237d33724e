#pragma once
// Field-by-field and bit-for-bit comparison of scenes, for the round-trip
// tests of the scene file format (test_scene_file.cpp, test_builtin_scenes.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <type_traits>

#include "demos/scene_file.hpp"
#include "demos/scene_spec.hpp"
#include "xpbd/xpbd.hpp"

namespace xpbd_demos::test {

// Bit-for-bit equality of two compiled models: particle arrays, every
// constraint element's particles and material, and 5 steps of the solver
// (which reads everything else: rest values, planes, pins).
inline void expect_same_model(const xpbd::Model& a, const xpbd::Model& b) {
  EXPECT_EQ(a.inv_mass, b.inv_mass);
  EXPECT_EQ(a.radius, b.radius);
  EXPECT_TRUE(a.x0 == b.x0);
  EXPECT_TRUE(a.v0 == b.v0);
  EXPECT_TRUE(a.pin_target0 == b.pin_target0);
  EXPECT_EQ(a.collision_triangles, b.collision_triangles);
  EXPECT_EQ(a.global_volume_tris, b.global_volume_tris);
  EXPECT_EQ(a.global_volume_verts, b.global_volume_verts);
  ASSERT_EQ(a.planes.size(), b.planes.size());
  for (std::size_t k = 0; k < a.planes.size(); ++k) {
    EXPECT_EQ(a.planes[k].normal, b.planes[k].normal);
    EXPECT_EQ(a.planes[k].offset, b.planes[k].offset);
  }
  xpbd::for_each_constraint_type([&]<class T>(std::type_identity<T>) {
    const auto& ea = a.get<T>();
    const auto& eb = b.get<T>();
    ASSERT_EQ(ea.size(), eb.size());
    for (std::size_t k = 0; k < ea.size(); ++k) {
      if constexpr (xpbd::is_generic_constraint_v<T>) {
        EXPECT_EQ(ea[k].p, eb[k].p);
      }
      // The stored rest values, whichever the type has.
      if constexpr (requires { ea[k].rest; }) {
        EXPECT_EQ(ea[k].rest, eb[k].rest);
      }
      if constexpr (requires { ea[k].rest_angle; }) {
        EXPECT_EQ(ea[k].rest_angle, eb[k].rest_angle);
      }
      if constexpr (requires { ea[k].rest_volume; }) {
        EXPECT_EQ(ea[k].rest_volume, eb[k].rest_volume);
      }
      if constexpr (requires { ea[k].length; }) {
        EXPECT_EQ(ea[k].length, eb[k].length);
      }
      if constexpr (requires { ea[k].thickness; }) {
        EXPECT_EQ(ea[k].thickness, eb[k].thickness);
      }
      if constexpr (requires { ea[k].target; }) {
        EXPECT_EQ(ea[k].target, eb[k].target);
      }
      if constexpr (requires { ea[k].k; }) {
        EXPECT_EQ(ea[k].k, eb[k].k);
      }
      EXPECT_EQ(ea[k].mat.compliance, eb[k].mat.compliance);
      EXPECT_EQ(ea[k].mat.damping, eb[k].mat.damping);
      EXPECT_EQ(ea[k].mat.stiffness, eb[k].mat.stiffness);
    }
  });
  xpbd::State sa = xpbd::make_state(a), sb = xpbd::make_state(b);
  xpbd::StepConfig cfg;
  cfg.substeps = 4;
  cfg.iterations = 2;
  for (int i = 0; i < 5; ++i) {
    xpbd::step(a, sa, cfg);
    xpbd::step(b, sb, cfg);
  }
  EXPECT_TRUE(sa.x == sb.x);
  EXPECT_TRUE(sa.v == sb.v);
}

// The fields of the body's own shape kind (a shape writes only those).
inline void expect_same_body(const RigidSpec& a, const RigidSpec& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.shape.kind, b.shape.kind);
  switch (a.shape.kind) {
    case ShapeKind::sphere:
      EXPECT_EQ(a.shape.radius, b.shape.radius);
      break;
    case ShapeKind::box:
      EXPECT_EQ(a.shape.half_extents, b.shape.half_extents);
      break;
    case ShapeKind::capsule:
    case ShapeKind::cylinder:
      EXPECT_EQ(a.shape.radius, b.shape.radius);
      EXPECT_EQ(a.shape.height, b.shape.height);
      break;
    case ShapeKind::plane:
      EXPECT_EQ(a.shape.normal, b.shape.normal);
      EXPECT_EQ(a.shape.offset, b.shape.offset);
      break;
    case ShapeKind::convex_hull:
      EXPECT_TRUE(a.shape.points == b.shape.points);
      break;
    case ShapeKind::mesh:
      EXPECT_EQ(a.shape.mesh_file, b.shape.mesh_file);
      EXPECT_TRUE(a.shape.vertices == b.shape.vertices);
      EXPECT_EQ(a.shape.triangles, b.shape.triangles);
      EXPECT_EQ(a.shape.scale, b.shape.scale);
      break;
  }
  EXPECT_EQ(a.mass, b.mass);
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.orientation, b.orientation);
  EXPECT_EQ(a.velocity, b.velocity);
  EXPECT_EQ(a.angular_velocity, b.angular_velocity);
  EXPECT_EQ(a.friction, b.friction);
  EXPECT_EQ(a.restitution, b.restitution);
  EXPECT_EQ(a.linear_damping, b.linear_damping);
  EXPECT_EQ(a.angular_damping, b.angular_damping);
  EXPECT_EQ(a.kinematic, b.kinematic);
}

// s -> to_json -> text -> parse: the same scene, exactly. Returns the parsed
// scene.
inline SceneSpec round_trip(const SceneSpec& s) {
  const std::string text = scene_text(to_json(s));
  const SceneSpec back = parse_scene(parse_json_text(text, "round-trip"), "round-trip", s.base_dir);
  // Complete: writing the result again gives the same text.
  EXPECT_EQ(scene_text(to_json(back)), text);

  EXPECT_EQ(back.name, s.name);
  EXPECT_EQ(back.description, s.description);
  EXPECT_EQ(back.solver.method, s.solver.method);
  EXPECT_EQ(back.solver.dt, s.solver.dt);
  EXPECT_EQ(back.solver.substeps, s.solver.substeps);
  EXPECT_EQ(back.solver.iterations, s.solver.iterations);
  EXPECT_EQ(back.solver.frames, s.solver.frames);
  EXPECT_EQ(back.solver.drag, s.solver.drag);
  EXPECT_EQ(back.solver.alternate_sweeps, s.solver.alternate_sweeps);
  EXPECT_EQ(back.solver.coloured, s.solver.coloured);
  EXPECT_EQ(back.solver.direct_chains, s.solver.direct_chains);
  EXPECT_EQ(back.solver.chain_passes, s.solver.chain_passes);
  EXPECT_EQ(back.solver.chain_tolerance, s.solver.chain_tolerance);
  EXPECT_EQ(back.solver.hierarchy, s.solver.hierarchy);
  EXPECT_EQ(back.solver.hierarchy_slack, s.solver.hierarchy_slack);
  EXPECT_EQ(back.solver.gravity, s.solver.gravity);
  EXPECT_EQ(back.solver.bullet_kLST, s.solver.bullet_kLST);
  EXPECT_EQ(back.solver.max_strain, s.solver.max_strain);
  EXPECT_EQ(back.solver.tolerance, s.solver.tolerance);
  EXPECT_EQ(back.solver.tolerance_measure, s.solver.tolerance_measure);
  EXPECT_EQ(back.solver.penetration_tolerance, s.solver.penetration_tolerance);
  EXPECT_EQ(back.solver.max_substeps, s.solver.max_substeps);
  const SoftContactSpec &c0 = s.soft.contacts, &c1 = back.soft.contacts;
  EXPECT_EQ(c1.thickness, c0.thickness);
  EXPECT_EQ(c1.margin, c0.margin);
  EXPECT_EQ(c1.static_friction, c0.static_friction);
  EXPECT_EQ(c1.dynamic_friction, c0.dynamic_friction);
  EXPECT_EQ(c1.restitution, c0.restitution);
  EXPECT_EQ(c1.compliance, c0.compliance);
  EXPECT_EQ(c1.feature_spacing, c0.feature_spacing);
  EXPECT_EQ(c1.wedges, c0.wedges);
  EXPECT_EQ(back.soft.generators.size(), s.soft.generators.size());

  const ExpandedSoft e0 = expand(s.soft, s.base_dir), e1 = expand(back.soft, back.base_dir);
  EXPECT_EQ(e1.triangles, e0.triangles);
  EXPECT_EQ(e1.lines, e0.lines);
  EXPECT_EQ(e1.scene.self_collision.enabled, e0.scene.self_collision.enabled);
  EXPECT_EQ(e1.scene.self_collision.distance, e0.scene.self_collision.distance);
  EXPECT_EQ(e1.scene.self_collision.skip_connected, e0.scene.self_collision.skip_connected);
  expect_same_model(xpbd::compile(e0.scene), xpbd::compile(e1.scene));

  EXPECT_EQ(back.bodies.size(), s.bodies.size());
  for (std::size_t b = 0; b < std::min(back.bodies.size(), s.bodies.size()); ++b)
    expect_same_body(back.bodies[b], s.bodies[b]);
  EXPECT_EQ(back.attachments.size(), s.attachments.size());
  for (std::size_t a = 0; a < std::min(back.attachments.size(), s.attachments.size()); ++a) {
    EXPECT_EQ(back.attachments[a].particle, s.attachments[a].particle);
    EXPECT_EQ(back.attachments[a].body, s.attachments[a].body);
    EXPECT_EQ(back.attachments[a].local, s.attachments[a].local);
    EXPECT_EQ(back.attachments[a].compliance, s.attachments[a].compliance);
  }
  return back;
}

}  // namespace xpbd_demos::test
