#include "pair_culling.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace xpbd_bullet::detail {
namespace {

constexpr std::int64_t kMaxCells = 512;  // cells one candidate box may cover in the grid
constexpr std::size_t kPiece = 1024;     // particles per piece of the pair search


}  // namespace

void find_pairs(const std::vector<Vec3>& x, const std::vector<Real>& inv_mass, ContactScratch& sc,
                xpbd::Workers* workers) {
  using xpbd::Cell;
  namespace hd = xpbd::detail;
  const std::size_t n = x.size();
  const std::size_t nc = sc.candidates.size();

  // grid_reach: twice the mean half size (finite ones) of the movable particles.
  Real sum = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (inv_mass[i] != Real(0) && std::isfinite(sc.half[i])) sum += sc.half[i], ++count;
  const Real grid_reach = count > 0 ? Real(2) * sum / Real(count) : Real(0);

  // Cell size: the median largest side of the candidate boxes grown by grid_reach.
  sc.sides.clear();
  for (const Candidate& c : sc.candidates)
    if (c.box.lo.allFinite() && c.box.hi.allFinite())
      sc.sides.push_back((c.box.hi - c.box.lo).maxCoeff() + Real(2) * grid_reach);
  Real cell = 1;
  if (!sc.sides.empty()) {
    const auto mid = sc.sides.begin() + std::ptrdiff_t(sc.sides.size() / 2);
    std::nth_element(sc.sides.begin(), mid, sc.sides.end());
    cell = *mid;
  }
  if (!(cell > Real(0)) || !std::isfinite(cell)) cell = 1;  // m; any positive size is correct
  const Real inv_cell = Real(1) / cell;

  // Candidates into the cells of their box grown by grid_reach (plus a
  // round-off allowance for x_i +- half_i). cell_at is monotone, so a centre
  // x_i with half_i <= grid_reach whose cube overlaps the box lies in one of
  // those cells.
  sc.entries.clear();
  sc.wide.clear();
  for (std::size_t k = 0; k < nc; ++k) {
    Candidate& c = sc.candidates[k];
    c.in_grid = false;
    if (c.box.lo.allFinite() && c.box.hi.allFinite()) {
      const Real scale = std::max(c.box.lo.cwiseAbs().maxCoeff(), c.box.hi.cwiseAbs().maxCoeff());
      const Real grow =
          grid_reach + Real(4) * xpbd::kDegenerateRel * (Real(1) + grid_reach + scale);
      const Cell lo = hd::cell_at(c.box.lo.array() - grow, inv_cell);
      const Cell hi = hd::cell_at(c.box.hi.array() + grow, inv_cell);
      // Cells covered, stopping before the product can overflow (each
      // factor is at most 2^31 + 1).
      std::int64_t cells = 1;
      for (int a = 0; a < 3 && cells <= kMaxCells; ++a)
        cells *= std::int64_t(hi[a]) - std::int64_t(lo[a]) + 1;
      if (cells <= kMaxCells) {
        Cell q;
        for (q[2] = lo[2]; q[2] <= hi[2]; ++q[2])
          for (q[1] = lo[1]; q[1] <= hi[1]; ++q[1])
            for (q[0] = lo[0]; q[0] <= hi[0]; ++q[0]) sc.entries.push_back({q, Index(k)});
        c.in_grid = true;
      }
    }
    if (!c.in_grid) sc.wide.push_back(Index(k));
  }

  // Hash table of 2^k >= 2 entries buckets, filled by a counting sort.
  const std::size_t table = std::bit_ceil(std::max<std::size_t>(2 * sc.entries.size(), 1));
  const auto mask = static_cast<std::uint32_t>(table - 1);
  sc.bucket_begin.assign(table + 1, 0);
  for (const GridEntry& e : sc.entries) ++sc.bucket_begin[hd::bucket_of(e.cell, mask) + 1];
  for (std::size_t b = 0; b < table; ++b) sc.bucket_begin[b + 1] += sc.bucket_begin[b];
  sc.grid.resize(sc.entries.size());
  for (const GridEntry& e : sc.entries) sc.grid[std::size_t(sc.bucket_begin[hd::bucket_of(e.cell, mask)]++)] = e;
  for (std::size_t b = table; b > 0; --b) sc.bucket_begin[b] = sc.bucket_begin[b - 1];
  sc.bucket_begin[0] = 0;

  // Overlapping pairs, particle by particle in increasing order (in pieces
  // of kPiece particles on the pool, each into its own list).
  const std::size_t pieces = (n + kPiece - 1) / kPiece;
  if (sc.found.size() < std::max<std::size_t>(pieces, 1)) sc.found.resize(std::max<std::size_t>(pieces, 1));
  for (auto& f : sc.found) f.clear();
  const auto pairs_of = [&](std::size_t begin, std::size_t end, std::size_t piece) {
    std::vector<std::array<Index, 2>>& found = sc.found[piece];
    for (std::size_t i = begin; i < end; ++i) {
      if (inv_mass[i] == Real(0)) continue;  // never gets a contact
      const Vec3& xi = x[i];
      const Real h = sc.half[i];
      auto test = [&](Index k) {
        if (overlaps(xi, h, sc.candidates[std::size_t(k)].box)) found.push_back({k, Index(i)});
      };
      if (h <= grid_reach && xi.allFinite()) {  // false for a NaN half size: tested against all
        const Cell q = hd::cell_at(xi, inv_cell);
        const std::uint32_t b = hd::bucket_of(q, mask);
        for (Index e = sc.bucket_begin[b]; e < sc.bucket_begin[b + 1]; ++e)
          if (hd::same_cell(sc.grid[std::size_t(e)].cell, q)) test(sc.grid[std::size_t(e)].candidate);
        for (Index k : sc.wide) test(k);
      } else {
        for (std::size_t k = 0; k < nc; ++k) test(Index(k));
      }
    }
  };
  if (workers != nullptr && workers->threads() > 1 && pieces > 1)
    workers->run(static_cast<int>(pieces), [&](int p) {
      const std::size_t b = std::size_t(p) * kPiece;
      pairs_of(b, std::min(n, b + kPiece), std::size_t(p));
    });
  else
    for (std::size_t p = 0; p < pieces; ++p) pairs_of(p * kPiece, std::min(n, (p + 1) * kPiece), p);

  // Grouped by candidate (a stable counting sort, over the pieces in order,
  // keeps the particles increasing).
  sc.pair_begin.assign(nc + 1, 0);
  std::size_t total = 0;
  for (const auto& found : sc.found) {
    for (const auto& f : found) ++sc.pair_begin[std::size_t(f[0]) + 1];
    total += found.size();
  }
  for (std::size_t k = 0; k < nc; ++k) sc.pair_begin[k + 1] += sc.pair_begin[k];
  sc.particles.resize(total);
  for (const auto& found : sc.found)
    for (const auto& f : found) sc.particles[std::size_t(sc.pair_begin[std::size_t(f[0])]++)] = f[1];
  for (std::size_t k = nc; k > 0; --k) sc.pair_begin[k] = sc.pair_begin[k - 1];
  sc.pair_begin[0] = 0;
}

}  // namespace xpbd_bullet::detail
