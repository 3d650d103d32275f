// Key containers for screened Poisson's octree (spsr.cpp): integer node and
// cell coordinates packed into 64-bit keys, an open-addressing map from keys
// to ints, containers that hold keys in 4^3 bricks (values at nodes, an
// index of a sorted key list), and sets of keys as sorted lists (union,
// dilation by a cell, cell corners). Internal to framework/reconstruct: the
// octree's levels, its extraction caches and its tests use them; nothing else
// should.
#pragma once

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <utility>
#include <vector>

namespace arcs::spsr_keys {

using Key = std::uint64_t;
constexpr int kBits = 21;
constexpr Key kMask = (Key(1) << kBits) - 1;
inline Key Pack(int x, int y, int z) {
  return Key(x) | (Key(y) << kBits) | (Key(z) << (2 * kBits));
}
inline int KX(Key k) { return static_cast<int>(k & kMask); }
inline int KY(Key k) { return static_cast<int>((k >> kBits) & kMask); }
inline int KZ(Key k) { return static_cast<int>((k >> (2 * kBits)) & kMask); }

// Open addressing (linear probing) from 64-bit keys to int.
class KeyMap {
 public:
  KeyMap() { Init(16); }
  void Reserve(std::size_t n) {
    if (n * 2 > keys_.size()) Rehash(n * 2);
  }
  int Find(Key k) const {
    std::size_t i = Mix(k) & mask_;
    while (true) {
      const Key q = keys_[i];
      if (q == k) return vals_[i];
      if (q == kEmpty) return -1;
      i = (i + 1) & mask_;
    }
  }
  // Inserts (k, v) unless k is present; returns the stored value.
  int Insert(Key k, int v) {
    if ((size_ + 1) * 2 > keys_.size()) Rehash(keys_.size() * 2);
    std::size_t i = Mix(k) & mask_;
    while (true) {
      const Key q = keys_[i];
      if (q == k) return vals_[i];
      if (q == kEmpty) {
        keys_[i] = k;
        vals_[i] = v;
        ++size_;
        return v;
      }
      i = (i + 1) & mask_;
    }
  }
  std::size_t size() const { return size_; }
  std::vector<Key> SortedKeys() const {
    std::vector<Key> out;
    out.reserve(size_);
    for (Key k : keys_)
      if (k != kEmpty) out.push_back(k);
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  static constexpr Key kEmpty = ~Key(0);
  static std::size_t Mix(Key k) {
    k ^= k >> 31;
    k *= 0x7fb5d329728ea185ULL;
    k ^= k >> 27;
    k *= 0x81dadef4bc2dd44dULL;
    k ^= k >> 33;
    return static_cast<std::size_t>(k);
  }
  void Init(std::size_t cap) {
    std::size_t c = 16;
    while (c < cap) c <<= 1;
    keys_.assign(c, kEmpty);
    vals_.assign(c, 0);
    mask_ = c - 1;
    size_ = 0;
  }
  void Rehash(std::size_t cap) {
    std::vector<Key> ok = std::move(keys_);
    std::vector<int> ov = std::move(vals_);
    Init(cap);
    for (std::size_t i = 0; i < ok.size(); ++i)
      if (ok[i] != kEmpty) Insert(ok[i], ov[i]);
  }
  std::vector<Key> keys_;
  std::vector<int> vals_;
  std::size_t mask_ = 0, size_ = 0;
};

// Values at grid nodes, in bricks of 4^3 nodes found by a hash of the
// brick's key (8^3 wasted memory: one brick per isolated node): a lookup
// probes a small table, then memory next to the neighbours' (marching cubes
// asks for the nodes around a surface, and each node's face neighbours),
// where one map of every node probes a table as large as all of them.
// Optionally the nodes of a coarser lattice (every 2^lattice_shift-th node,
// lattice_n per side: the complete level's, which the extraction reads
// everywhere) are held in a dense grid, so that they do not make a brick
// each.
template <class T>
class NodeCache {
 public:
  // A brick is 2^kBrickBits nodes a side.
  static constexpr int kBrickBits = 2;
  NodeCache() = default;
  NodeCache(int lattice_shift, int lattice_n)
      : shift_(lattice_shift), n_(lattice_n),
        dense_(static_cast<std::size_t>(lattice_n) * lattice_n * lattice_n) {
    val_.assign(dense_, T{});
    known_.assign(dense_, 0);
  }
  // Node k's value, or null when it is not known.
  const T* Lookup(Key k) const {
    const std::int64_t i = Slot(k);
    return i >= 0 && known_[static_cast<std::size_t>(i)] ? &val_[static_cast<std::size_t>(i)] : nullptr;
  }
  void Set(Key k, T v) {
    std::int64_t i = Slot(k);
    if (i < 0) {
      const int b = bricks_.Insert(BrickKey(k), static_cast<int>((val_.size() - dense_) / kCount));
      val_.resize(val_.size() + kCount, T{});
      known_.resize(known_.size() + kCount, 0);
      i = static_cast<std::int64_t>(dense_) + static_cast<std::int64_t>(b) * kCount + Local(k);
    }
    val_[static_cast<std::size_t>(i)] = v;
    known_[static_cast<std::size_t>(i)] = 1;
  }
  // Set(keys[i], vals[i]) for every i in order: the same values in the same
  // slots, the bricks made in the same order. A run of keys in one brick
  // (sorted keys come four at a time along x) looks the brick up once.
  void SetMany(const std::vector<Key>& keys, const std::vector<T>& vals) {
    Key last = ~Key(0);
    std::size_t base = 0;
    for (std::size_t n = 0; n < keys.size(); ++n) {
      const Key k = keys[n];
      if (const std::int64_t d = DenseSlot(k); d >= 0) {
        val_[static_cast<std::size_t>(d)] = vals[n];
        known_[static_cast<std::size_t>(d)] = 1;
        continue;
      }
      const Key bk = BrickKey(k);
      if (bk != last) {
        int b = bricks_.Find(bk);
        if (b < 0) {
          b = bricks_.Insert(bk, static_cast<int>((val_.size() - dense_) / kCount));
          val_.resize(val_.size() + kCount, T{});
          known_.resize(known_.size() + kCount, 0);
        }
        base = dense_ + static_cast<std::size_t>(b) * kCount;
        last = bk;
      }
      val_[base + Local(k)] = vals[n];
      known_[base + Local(k)] = 1;
    }
  }
  // Every known key, sorted.
  std::vector<Key> SortedKeys() const {
    std::vector<Key> out;
    for (std::size_t i = 0; i < dense_; ++i)
      if (known_[i]) {
        const int a = static_cast<int>(i % n_), b = static_cast<int>((i / n_) % n_), c = static_cast<int>(i / n_ / n_);
        out.push_back(Pack(a << shift_, b << shift_, c << shift_));
      }
    for (Key bk : bricks_.SortedKeys()) {
      const std::size_t base = dense_ + static_cast<std::size_t>(bricks_.Find(bk)) * kCount;
      const int x0 = KX(bk) << kShift, y0 = KY(bk) << kShift, z0 = KZ(bk) << kShift;
      for (int l = 0; l < kCount; ++l)
        if (known_[base + l])
          out.push_back(Pack(x0 + (l & kLow), y0 + ((l >> kShift) & kLow), z0 + (l >> (2 * kShift))));
    }
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  static constexpr int kShift = kBrickBits, kCount = 1 << (3 * kShift), kLow = (1 << kShift) - 1;
  static Key BrickKey(Key k) { return Pack(KX(k) >> kShift, KY(k) >> kShift, KZ(k) >> kShift); }
  static int Local(Key k) {
    return (KX(k) & kLow) | ((KY(k) & kLow) << kShift) | ((KZ(k) & kLow) << (2 * kShift));
  }
  // Node k's slot in the dense lattice, or -1 when it is not a lattice node.
  std::int64_t DenseSlot(Key k) const {
    const int x = KX(k), y = KY(k), z = KZ(k);
    if (shift_ >= 0 && ((x | y | z) & ((1 << shift_) - 1)) == 0) {
      const std::int64_t a = x >> shift_, b = y >> shift_, c = z >> shift_;
      if (a < n_ && b < n_ && c < n_) return a + n_ * (b + n_ * c);
    }
    return -1;
  }
  // The slot of node k, or -1 when its brick does not exist.
  std::int64_t Slot(Key k) const {
    if (const std::int64_t d = DenseSlot(k); d >= 0) return d;
    const int b = bricks_.Find(BrickKey(k));
    if (b < 0) return -1;
    return static_cast<std::int64_t>(dense_) + static_cast<std::int64_t>(b) * kCount + Local(k);
  }
  int shift_ = -1, n_ = 0;
  std::size_t dense_ = 0;
  KeyMap bricks_;
  std::vector<T> val_;
  std::vector<unsigned char> known_;
};

// Key -> position in a sorted key list, in bricks (NodeCache): the octree
// levels' node indices, which every stencil, prolongation and value lookup
// reads.
class BrickIndex {
 public:
  static BrickIndex IndexOf(const std::vector<Key>& sorted) {
    BrickIndex m;
    for (std::size_t i = 0; i < sorted.size(); ++i) m.c_.Set(sorted[i], static_cast<int>(i));
    return m;
  }
  int Find(Key k) const {
    const int* i = c_.Lookup(k);
    return i ? *i : -1;
  }
 private:
  NodeCache<int> c_;
};

// Sorted sets of keys (the octree's cells and nodes, built by merging sorted
// lists, not by hashing).
//
// Sorts keys and drops repeats (in parallel: equal keys are the same bits,
// so the result is the one sorted set).
inline void SortUnique(std::vector<Key>& keys) {
  tbb::parallel_sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
}

// a ∪ b, both sorted and distinct.
inline std::vector<Key> Union(const std::vector<Key>& a, const std::vector<Key>& b) {
  std::vector<Key> out;
  out.reserve(a.size() + b.size());
  std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

// The set `in` (sorted, distinct) shifted along `axis` by each offset in
// [lo, hi] (lo <= 0 <= hi, at most three offsets), keeping coordinates in
// [0, limit): their union, sorted. A shift adds a constant to every key
// whose coordinate stays in range, so each shifted copy is sorted and one
// merge makes the union.
inline std::vector<Key> ShiftUnion(const std::vector<Key>& in, int axis, int lo, int hi, int limit) {
  const int shift = kBits * axis;
  const Key unit = Key(1) << shift;
  const int m = std::min(hi - lo + 1, 3);
  std::size_t at[3] = {0, 0, 0};
  Key cur[3] = {0, 0, 0};
  bool live[3] = {false, false, false};
  // Copy j: `in` shifted by lo + j; the next key in range goes to cur[j].
  auto advance = [&](int j) {
    const int off = lo + j;
    while (at[j] < in.size()) {
      const Key k = in[at[j]++];
      const int c = static_cast<int>((k >> shift) & kMask) + off;
      if (c >= 0 && c < limit) {
        cur[j] = off >= 0 ? k + unit * static_cast<Key>(off) : k - unit * static_cast<Key>(-off);
        return true;
      }
    }
    return false;
  };
  for (int j = 0; j < m; ++j) live[j] = advance(j);
  std::vector<Key> out;
  out.reserve(in.size() * 2);
  for (;;) {
    int best = -1;
    for (int j = 0; j < m; ++j)
      if (live[j] && (best < 0 || cur[j] < cur[best])) best = j;
    if (best < 0) break;
    const Key k = cur[best];
    out.push_back(k);
    for (int j = 0; j < m; ++j)
      if (live[j] && cur[j] == k) live[j] = advance(j);
  }
  return out;
}

// Every cell within one cell (the 3 x 3 x 3 block) of a cell of `cells`,
// on a grid of res cells per side: separable, one axis at a time.
inline std::vector<Key> DilateCells(const std::vector<Key>& cells, int res) {
  return ShiftUnion(ShiftUnion(ShiftUnion(cells, 0, -1, 1, res), 1, -1, 1, res), 2, -1, 1, res);
}

// The corners of the cells (nodes (x..x+1, y..y+1, z..z+1)), sorted.
inline std::vector<Key> CellCorners(const std::vector<Key>& cells) {
  constexpr int kAny = 1 << kBits;  // corners are never out of range
  return ShiftUnion(ShiftUnion(ShiftUnion(cells, 0, 0, 1, kAny), 1, 0, 1, kAny), 2, 0, 1, kAny);
}

// The 27-point neighbourhoods of the grid nodes q[0] < q[1] < ... < q[count
// - 1] (keys, coordinates in [0, res]) in `nodes` (sorted, distinct):
// out[27 i + o] is the index in `nodes` of q[i] + (dx, dy, dz), o = (dx + 1)
// + 3 (dy + 1) + 9 (dz + 1), or -1 when that node is not in the list or lies
// outside [0, res]^3 (what 27 calls of BrickIndex::Find give). For each of
// the nine (dy, dz) the keys sought grow with i, so a pointer per row walks
// the list forward: no hashing.
inline void NeighbourRowsOf(const std::vector<Key>& nodes, int res, const Key* q, std::size_t count, int* out) {
  const std::size_t n = nodes.size();
  std::size_t ptr[9];
  bool started[9] = {false, false, false, false, false, false, false, false, false};
  for (std::size_t i = 0; i < count; ++i, out += 27) {
    const int x = KX(q[i]), y = KY(q[i]), z = KZ(q[i]);
    for (int r = 0; r < 9; ++r) {
      const int yy = y + r % 3 - 1, zz = z + r / 3 - 1;
      int* row = out + 3 * r;
      if (yy < 0 || zz < 0 || yy > res || zz > res) {
        row[0] = row[1] = row[2] = -1;
        continue;
      }
      const Key first = Pack(std::max(x - 1, 0), yy, zz);
      std::size_t& p = ptr[r];
      if (!started[r]) {
        p = static_cast<std::size_t>(std::lower_bound(nodes.begin(), nodes.end(), first) - nodes.begin());
        started[r] = true;
      }
      while (p < n && nodes[p] < first) ++p;
      std::size_t j = p;
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx;
        if (xx < 0 || xx > res) {
          row[dx + 1] = -1;
          continue;
        }
        const Key k = Pack(xx, yy, zz);
        while (j < n && nodes[j] < k) ++j;
        row[dx + 1] = j < n && nodes[j] == k ? static_cast<int>(j) : -1;
      }
    }
  }
}

// Rows [begin, end) of the list's own 27-neighbour table (its nodes' rows).
inline void NeighbourRows(const std::vector<Key>& nodes, int res, std::size_t begin, std::size_t end, int* out) {
  NeighbourRowsOf(nodes, res, nodes.data() + begin, end - begin, out);
}

}  // namespace arcs::spsr_keys
