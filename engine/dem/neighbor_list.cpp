#include "engine/dem/neighbor_list.hpp"

#include <algorithm>
#include <cmath>

#include "engine/core/error.hpp"

namespace grainflow::dem {

namespace {

constexpr std::size_t kChunk = 1024;

struct Candidate {
  std::uint32_t j;
  std::uint8_t shift;
};

void wrap_positions(Particles& p, const Box& box) {
  for (int a = 0; a < 3; ++a) {
    if (!box.periodic[a]) continue;
    const double L = box.len[a], lo = box.lo[a];
    for (std::size_t i = 0; i < p.n; ++i) {
      double& x = p.x[3 * i + a];
      if (x < lo || x >= lo + L) {
        x -= L * std::floor((x - lo) / L);
        if (x >= lo + L) x = lo;  // rounding at the upper edge
      }
    }
  }
}

// Cell grid of the chain-cell search (seed 000 §3.2): cells at least `cell_min` wide.
// The seed's HEAD/LIST chains are stored as a counting sort: particles of cell c are
// order[start[c] .. start[c+1]) in ascending index, with their positions copied in the
// same order, so a 27-cell sweep reads contiguous memory (the O(N) rebuild).
struct CellGrid {
  int nc[3];
  double inv[3];
  std::vector<std::uint32_t> start;   // ncell + 1
  std::vector<std::uint32_t> order;   // particle indices grouped by cell
  std::vector<double> cx;             // 3 per entry of order: positions
  std::vector<double> cr;             // radius per entry of order
  std::vector<std::int32_t> cell_of;
  std::vector<std::uint32_t> fill;    // counting-sort cursor per cell

  int coord(const Box& box, int a, double x) const {
    const int c = static_cast<int>(std::floor((x - box.lo[a]) * inv[a]));
    return std::clamp(c, 0, nc[a] - 1);  // open top / rounding: clamping keeps the stencil valid
  }
};

void fill_cells(CellGrid& g, const Particles& p, const Box& box, double cell_min) {
  for (int a = 0; a < 3; ++a) {
    g.nc[a] = std::max(1, static_cast<int>(std::floor(box.len[a] / cell_min)));
    g.nc[a] = std::min(g.nc[a], 1 << 10);
  }
  // A sparse huge box must not allocate a giant cell array (two spheres in a 10 m box
  // took 1024³ cells, 8.6 GB and 27 s): more cells than a few per particle only hold
  // empty ones, so the grid is coarsened — cells stay at least cell_min wide, the pairs
  // found are the same (the table's order does not depend on the grid).
  const double limit = std::max(4096.0, 8.0 * double(p.n));
  while (double(g.nc[0]) * g.nc[1] * g.nc[2] > limit) {
    const int a = g.nc[0] >= g.nc[1] && g.nc[0] >= g.nc[2] ? 0 : g.nc[1] >= g.nc[2] ? 1 : 2;
    g.nc[a] = std::max(1, g.nc[a] / 2);
  }
  for (int a = 0; a < 3; ++a) g.inv[a] = g.nc[a] / box.len[a];
  const std::size_t ncell = static_cast<std::size_t>(g.nc[0]) * g.nc[1] * g.nc[2];
  g.start.assign(ncell + 1, 0);
  g.cell_of.resize(p.n);
  for (std::size_t i = 0; i < p.n; ++i) {
    const int cx = g.coord(box, 0, p.x[3 * i]), cy = g.coord(box, 1, p.x[3 * i + 1]),
              cz = g.coord(box, 2, p.x[3 * i + 2]);
    const int c = cx + g.nc[0] * (cy + g.nc[1] * cz);
    g.cell_of[i] = c;
    ++g.start[c + 1];
  }
  for (std::size_t c = 0; c < ncell; ++c) g.start[c + 1] += g.start[c];
  g.order.resize(p.n);
  g.cx.resize(3 * p.n);
  g.cr.resize(p.n);
  g.fill.assign(g.start.begin(), g.start.end() - 1);
  for (std::size_t i = 0; i < p.n; ++i) {
    const std::uint32_t k = g.fill[g.cell_of[i]]++;
    g.order[k] = static_cast<std::uint32_t>(i);
    g.cx[3 * k] = p.x[3 * i];
    g.cx[3 * k + 1] = p.x[3 * i + 1];
    g.cx[3 * k + 2] = p.x[3 * i + 2];
    g.cr[k] = p.radius[i];
  }
}

inline bool within(const Particles& p, const Box& box, std::size_t i, std::size_t j, int s,
                   double extra) {
  const double dx = p.x[3 * j] + box.shift[s][0] - p.x[3 * i];
  const double dy = p.x[3 * j + 1] + box.shift[s][1] - p.x[3 * i + 1];
  const double dz = p.x[3 * j + 2] + box.shift[s][2] - p.x[3 * i + 2];
  const double cut = p.radius[i] + p.radius[j] + extra;
  return dx * dx + dy * dy + dz * dz < cut * cut;
}

// Candidates come from up to 27 cells in cell order; the table wants them by ascending j
// (as the N² search yields them). The lists are short (a dozen entries): insertion sort.
void sort_candidates(Candidate* c, std::size_t n) {
  for (std::size_t a = 1; a < n; ++a) {
    const Candidate v = c[a];
    std::size_t b = a;
    for (; b > 0 && (c[b - 1].j > v.j || (c[b - 1].j == v.j && c[b - 1].shift > v.shift)); --b) c[b] = c[b - 1];
    c[b] = v;
  }
}

// Writes the neighbours j > i of particle i to out[0, count) and returns count; `out`
// only grows (no per-particle clearing).
std::size_t candidates_cells(const CellGrid& g, const Particles& p, const Box& box, double extra,
                             std::size_t i, std::vector<Candidate>& out) {
  const int c = g.cell_of[i];
  const int ci[3] = {c % g.nc[0], (c / g.nc[0]) % g.nc[1], c / (g.nc[0] * g.nc[1])};
  struct Range {
    std::uint32_t k0, k1;
    int s;
  };
  Range cells[27];
  int ncells = 0;
  std::size_t total = 0;
  for (int oz = -1; oz <= 1; ++oz)
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox) {
        const int o[3] = {ox, oy, oz};
        int cc[3], sc[3];
        bool skip = false;
        for (int a = 0; a < 3 && !skip; ++a) {
          cc[a] = ci[a] + o[a];
          sc[a] = 1;
          if (cc[a] < 0 || cc[a] >= g.nc[a]) {
            if (!box.periodic[a]) {
              skip = true;
            } else if (cc[a] < 0) {
              cc[a] += g.nc[a];
              sc[a] = 0;
            } else {
              cc[a] -= g.nc[a];
              sc[a] = 2;
            }
          }
        }
        if (skip) continue;
        const std::size_t cell = cc[0] + g.nc[0] * (cc[1] + static_cast<std::size_t>(g.nc[1]) * cc[2]);
        cells[ncells++] = {g.start[cell], g.start[cell + 1], sc[0] + 3 * sc[1] + 9 * sc[2]};
        total += g.start[cell + 1] - g.start[cell];
      }
  if (out.size() < total + 1) out.resize(2 * total + 1);
  Candidate* o = out.data();
  std::size_t n = 0;
  const double xi = p.x[3 * i], yi = p.x[3 * i + 1], zi = p.x[3 * i + 2], ri = p.radius[i];
  for (int cn = 0; cn < ncells; ++cn) {
    const double* sh = box.shift[cells[cn].s];
    const auto s = static_cast<std::uint8_t>(cells[cn].s);
    // A cell lists ascending indices: skip the cells without j > i as a whole, and the
    // part below i of the others, before the per-candidate loop.
    const std::uint32_t k1 = cells[cn].k1;
    if (k1 == cells[cn].k0 || g.order[k1 - 1] <= i) continue;
    std::uint32_t k = cells[cn].k0;
    while (g.order[k] <= i) ++k;
    for (; k < k1; ++k) {
      const std::uint32_t j = g.order[k];
      // The same arithmetic as within() (the N² reference): identical tables.
      const double dx = g.cx[3 * k] + sh[0] - xi;
      const double dy = g.cx[3 * k + 1] + sh[1] - yi;
      const double dz = g.cx[3 * k + 2] + sh[2] - zi;
      const double cut = ri + g.cr[k] + extra;
      // Branch-free append: whether a cell mate is a neighbour is hard to predict.
      o[n] = {j, s};
      n += dx * dx + dy * dy + dz * dz < cut * cut;
    }
  }
  sort_candidates(out.data(), n);
  return n;
}

void candidates_all_pairs(const Particles& p, const Box& box, double extra, std::size_t i,
                          std::vector<Candidate>& out) {
  for (std::size_t j = i + 1; j < p.n; ++j) {
    // Minimum image: the one shift per periodic axis that can be within range (L > 2 cut).
    int sc[3];
    for (int a = 0; a < 3; ++a) {
      sc[a] = 1;
      if (!box.periodic[a]) continue;
      const double d = p.x[3 * j + a] - p.x[3 * i + a];
      if (d > 0.5 * box.len[a]) sc[a] = 0;
      else if (d < -0.5 * box.len[a]) sc[a] = 2;
    }
    const int s = sc[0] + 3 * sc[1] + 9 * sc[2];
    if (within(p, box, i, j, s, extra)) out.push_back({static_cast<std::uint32_t>(j), static_cast<std::uint8_t>(s)});
  }
}

}  // namespace

void build_neighbor_list(NeighborList& list, Particles& p, const Box& box, double skin,
                         double extra_range, NeighborMethod method) {
  wrap_positions(p, box);
  const double extra = skin + extra_range;
  double rmax = 0.0;
  for (std::size_t i = 0; i < p.n; ++i) rmax = std::max(rmax, p.radius[i]);
  const double cut_max = 2.0 * rmax + extra;
  for (int a = 0; a < 3; ++a)
    if (box.periodic[a] && box.len[a] <= 2.0 * cut_max)
      throw Error("dem: periodic box length along axis " + std::to_string(a) + " is " +
                  std::to_string(box.len[a]) + " m; it must exceed twice the neighbour search distance (" +
                  std::to_string(2.0 * cut_max) + " m = 2 × (largest diameter + skin + cohesion range))");

  // Buffers kept from build to build (per calling thread): a rebuild then touches no
  // fresh pages, which otherwise cost as much as the search itself at large N.
  struct Workspace {
    CellGrid grid;
    std::vector<std::vector<Candidate>> chunk_pairs;
    std::vector<std::uint32_t> count, old_first, old_partner;
    std::vector<std::uint8_t> old_flags;
    std::vector<double> old_hist;
  };
  thread_local Workspace ws;
  CellGrid& grid = ws.grid;
  if (method == NeighborMethod::ChainCells) fill_cells(grid, p, box, cut_max);

  const std::size_t n = p.n;
  const std::size_t nchunks = (n + kChunk - 1) / kChunk;
  auto& chunk_pairs = ws.chunk_pairs;
  if (chunk_pairs.size() < nchunks) chunk_pairs.resize(nchunks);
  auto& count = ws.count;
  count.assign(n + 1, 0);

#pragma omp parallel if (nchunks > 1)
  {
    std::vector<Candidate> buf;
    buf.reserve(64);
#pragma omp for schedule(dynamic, 1)
    for (std::size_t c = 0; c < nchunks; ++c) {
      auto& out = chunk_pairs[c];
      out.clear();
      const std::size_t i1 = std::min(n, (c + 1) * kChunk);
      for (std::size_t i = c * kChunk; i < i1; ++i) {
        std::size_t m;
        if (method == NeighborMethod::ChainCells) {
          m = candidates_cells(grid, p, box, extra, i, buf);
        } else {
          buf.clear();
          candidates_all_pairs(p, box, extra, i, buf);
          m = buf.size();
        }
        count[i] = static_cast<std::uint32_t>(m);
        out.insert(out.end(), buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(m));
      }
    }
  }

  // New table; carry the history of pairs present in both tables (both sorted by j).
  struct {
    std::vector<std::uint32_t>& first;
    std::vector<std::uint32_t>& partner;
    std::vector<std::uint8_t>& flags;
    std::vector<double>& hist;
  } old{ws.old_first, ws.old_partner, ws.old_flags, ws.old_hist};
  std::swap(old.first, list.first);
  std::swap(old.partner, list.partner);
  std::swap(old.flags, list.flags);
  std::swap(old.hist, list.hist);
  const int H = list.history_size;

  list.first.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) list.first[i + 1] = list.first[i] + count[i];
  const std::size_t P = list.first[n];
  list.partner.resize(P);
  list.shift.resize(P);
  list.flags.assign(P, 0);
  list.hist.assign(P * H, 0.0);
#pragma omp parallel for schedule(static) if (nchunks > 1)
  for (std::size_t c = 0; c < nchunks; ++c) {
    std::size_t k = list.first[c * kChunk];
    for (const Candidate& cd : chunk_pairs[c]) {
      list.partner[k] = cd.j;
      list.shift[k] = cd.shift;
      ++k;
    }
  }
  if (!old.first.empty() && old.first.size() == n + 1) {
#pragma omp parallel for schedule(static) if (n > 4096)
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t a = old.first[i], ae = old.first[i + 1];
      for (std::uint32_t b = list.first[i]; b < list.first[i + 1] && a < ae; ++b) {
        while (a < ae && old.partner[a] < list.partner[b]) ++a;
        if (a < ae && old.partner[a] == list.partner[b]) {
          list.flags[b] = old.flags[a] & NeighborList::kHistory;
          for (int h = 0; h < H; ++h) list.hist[std::size_t(b) * H + h] = old.hist[std::size_t(a) * H + h];
          ++a;
        }
      }
    }
  }

  index_pairs(list, p, extra_range);
  list.xref = p.x;
  ++list.builds;
}

std::size_t force_chunk_size(std::size_t n) { return std::max<std::size_t>(128, (n + 15) / 16); }

void index_pairs(NeighborList& list, const Particles& p, double range) {
  const std::size_t n = p.n;
  list.owner.resize(list.partner.size());
  list.reach_sq.resize(list.partner.size());
#pragma omp parallel for schedule(static) if (n > 4096)
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t q = list.first[i]; q < list.first[i + 1]; ++q) {
      list.owner[q] = static_cast<std::uint32_t>(i);
      const double reach = (p.radius[i] + range) + p.radius[list.partner[q]];
      list.reach_sq[q] = reach * reach;
    }
  const std::size_t K = force_chunk_size(n);
  list.rfirst.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t end = std::min(n, (i / K + 1) * K);
    for (std::uint32_t q = list.first[i]; q < list.first[i + 1]; ++q)
      if (list.partner[q] >= end) ++list.rfirst[list.partner[q] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) list.rfirst[i + 1] += list.rfirst[i];
  list.cross_slot.assign(list.partner.size(), 0);
  list.chunk_dep.resize((n + K - 1) / K);
  for (std::size_t c = 0; c < list.chunk_dep.size(); ++c) list.chunk_dep[c] = static_cast<std::uint32_t>(c);
  std::vector<std::uint32_t> fill(list.rfirst.begin(), list.rfirst.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t end = std::min(n, (i / K + 1) * K);
    for (std::uint32_t q = list.first[i]; q < list.first[i + 1]; ++q) {
      const std::size_t j = list.partner[q];
      if (j < end) continue;
      list.cross_slot[q] = fill[j]++;
      std::uint32_t& dep = list.chunk_dep[j / K];
      dep = std::min(dep, static_cast<std::uint32_t>(i / K));
    }
  }
  list.cross_force.assign(6 * std::size_t(list.rfirst[n]), 0.0);
}

double max_displacement_sq(const NeighborList& list, const Particles& p) {
  double m = 0.0;
  for (std::size_t i = 0; i < p.n; ++i) {
    const double dx = p.x[3 * i] - list.xref[3 * i], dy = p.x[3 * i + 1] - list.xref[3 * i + 1],
                 dz = p.x[3 * i + 2] - list.xref[3 * i + 2];
    m = std::max(m, dx * dx + dy * dy + dz * dz);
  }
  return m;
}

}  // namespace grainflow::dem
