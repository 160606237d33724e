// The collision triangles' hierarchy in FCL (triangle_bvh.hpp).
#include "triangle_bvh.hpp"

#include <algorithm>

#include <fcl/math/bv/utility.h>  // fit(), which BVH_model-inl.h uses
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/AABB.h>

namespace xpbd_bullet::detail {

namespace {
using Box = fcl::AABB<double>;  // FCL in double in both builds: the boxes only filter
using Point = fcl::Vector3<double>;
Point point(const xpbd::Vec3& p) { return Point(double(p.x()), double(p.y()), double(p.z())); }
}  // namespace

struct TriangleBvh::Impl {
  std::unique_ptr<fcl::BVHModel<Box>> model;  // not assignable: replaced whole
  std::vector<std::array<xpbd::Index, 3>> tris;  // what the model was built for
  std::vector<Point> points;                     // scratch
  bool built = false;
  mutable std::vector<int> stack;  // scratch of query()
};

TriangleBvh::TriangleBvh() : impl_(std::make_unique<Impl>()) {}
TriangleBvh::~TriangleBvh() = default;

void TriangleBvh::update(const std::vector<std::array<xpbd::Index, 3>>& tris, const std::vector<xpbd::Vec3>& x,
                         const std::vector<xpbd::Vec3>& v, xpbd::Real dt) {
  Impl& m = *impl_;
  const std::size_t n = x.size();
  m.points.resize(n);
  if (!m.built || tris != m.tris) {
    // Built over the start positions; the refit below gives the swept boxes.
    m.model = std::make_unique<fcl::BVHModel<Box>>();
    std::vector<fcl::Triangle> t;
    t.reserve(tris.size());
    for (const auto& tri : tris)
      t.emplace_back(std::size_t(tri[0]), std::size_t(tri[1]), std::size_t(tri[2]));
    for (std::size_t i = 0; i < n; ++i) m.points[i] = point(x[i]);
    m.model->beginModel(int(t.size()), int(n));
    m.model->addSubModel(m.points, t);
    m.model->endModel();
    m.tris = tris;
    m.built = true;
  }
  // The end of the step without contacts; then the start, written over the
  // frame FCL keeps as the previous one, so that each leaf's box is fitted
  // over both.
  m.model->beginUpdateModel();
  for (std::size_t i = 0; i < n; ++i) m.points[i] = point(x[i] + dt * v[i]);
  m.model->updateSubModel(m.points);
  for (std::size_t i = 0; i < n; ++i) m.model->prev_vertices[i] = point(x[i]);
  m.model->endUpdateModel(true, true);
}

void TriangleBvh::query(const xpbd::Vec3& lo, const xpbd::Vec3& hi, std::vector<int>& out) const {
  const Impl& m = *impl_;
  if (!m.built || m.model->getNumBVs() == 0) return;
  const Point a = point(lo), b = point(hi);
  const std::size_t first = out.size();
  m.stack.clear();
  m.stack.push_back(0);
  while (!m.stack.empty()) {
    const int id = m.stack.back();
    m.stack.pop_back();
    const fcl::BVNode<Box>& node = m.model->getBV(id);
    if ((b.array() < node.bv.min_.array()).any() || (a.array() > node.bv.max_.array()).any()) continue;
    if (node.isLeaf()) {
      out.push_back(node.primitiveId());
    } else {
      m.stack.push_back(node.rightChild());
      m.stack.push_back(node.leftChild());
    }
  }
  std::sort(out.begin() + std::ptrdiff_t(first), out.end());
}

}  // namespace xpbd_bullet::detail
