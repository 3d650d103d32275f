// The screened Poisson octree's key containers (spsr_keys.h) against the
// standard library's map and set on random keys: the same lookups, the same
// sorted key lists, with and without the dense lattice.
#include "framework/reconstruct/spsr_keys.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>

namespace arcs::spsr_keys {
namespace {

// Keys clustered like an octree level's nodes (a few dense patches plus
// scattered nodes), coordinates below 2^10.
std::vector<Key> RandomKeys(std::mt19937* rng, int count) {
  std::uniform_int_distribution<int> far(0, 1023), near(-6, 6), pick(0, 3);
  std::vector<Key> out;
  int cx = 512, cy = 512, cz = 512;
  for (int i = 0; i < count; ++i) {
    if (pick(*rng) == 0) cx = far(*rng), cy = far(*rng), cz = far(*rng);
    const int x = std::clamp(cx + near(*rng), 0, 1023), y = std::clamp(cy + near(*rng), 0, 1023),
              z = std::clamp(cz + near(*rng), 0, 1023);
    out.push_back(Pack(x, y, z));
  }
  return out;
}

TEST(SpsrKeys, PackRoundTrips) {
  const Key k = Pack(3, (1 << 21) - 1, 77);
  EXPECT_EQ(KX(k), 3);
  EXPECT_EQ(KY(k), (1 << 21) - 1);
  EXPECT_EQ(KZ(k), 77);
  EXPECT_NE(Pack(1, 0, 0), Pack(0, 1, 0));
}

TEST(SpsrKeys, KeyMapMatchesStdMapThroughRehashes) {
  std::mt19937 rng(7);
  KeyMap m;
  std::map<Key, int> ref;
  const std::vector<Key> keys = RandomKeys(&rng, 20000);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const int stored = m.Insert(keys[i], static_cast<int>(i));
    const auto [it, fresh] = ref.emplace(keys[i], static_cast<int>(i));
    EXPECT_EQ(stored, it->second);  // an existing key keeps its first value
    (void)fresh;
  }
  EXPECT_EQ(m.size(), ref.size());
  for (const auto& [k, v] : ref) EXPECT_EQ(m.Find(k), v);
  for (const Key k : RandomKeys(&rng, 2000)) {
    if (!ref.count(k)) {
      EXPECT_EQ(m.Find(k), -1);
    }
  }
  std::vector<Key> sorted;
  for (const auto& kv : ref) sorted.push_back(kv.first);
  EXPECT_EQ(m.SortedKeys(), sorted);
}

void CheckNodeCache(NodeCache<double> cache, const std::vector<Key>& keys, std::mt19937* rng) {
  std::map<Key, double> ref;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    cache.Set(keys[i], 0.5 * static_cast<double>(i));  // a later Set overwrites
    ref[keys[i]] = 0.5 * static_cast<double>(i);
  }
  for (const auto& [k, v] : ref) {
    const double* got = cache.Lookup(k);
    ASSERT_NE(got, nullptr);
    EXPECT_EQ(*got, v);
  }
  // Neighbours of known nodes share their bricks (or the lattice) but were
  // never set: unknown.
  for (const Key k : RandomKeys(rng, 3000)) {
    if (!ref.count(k)) {
      EXPECT_EQ(cache.Lookup(k), nullptr);
    }
  }
  std::vector<Key> sorted;
  for (const auto& kv : ref) sorted.push_back(kv.first);
  EXPECT_EQ(cache.SortedKeys(), sorted);
}

TEST(SpsrKeys, NodeCacheMatchesStdMapWithAndWithoutLattice) {
  std::mt19937 rng(11);
  const std::vector<Key> keys = RandomKeys(&rng, 15000);
  CheckNodeCache(NodeCache<double>(), keys, &rng);
  // The complete level's lattice: every 8th node, 128 per side (covers
  // coordinates 0..1016; multiples of 8 beyond it go to bricks).
  CheckNodeCache(NodeCache<double>(3, 128), keys, &rng);
  // Lattice nodes only, and one past the lattice's end.
  std::vector<Key> lattice;
  for (int i = 0; i < 200; ++i) lattice.push_back(Pack(8 * (i % 128), 8 * (i / 7 % 128), 8 * (i / 3 % 128)));
  lattice.push_back(Pack(1024, 0, 0));
  CheckNodeCache(NodeCache<double>(3, 128), lattice, &rng);
}

// SetMany is the loop of Set: the same lookups and the same sorted keys,
// on random and on sorted keys, with and without the lattice, repeats
// included, and a later value overwrites an earlier one.
TEST(SpsrKeys, NodeCacheSetManyIsTheLoopOfSet) {
  std::mt19937 rng(17);
  std::vector<Key> keys = RandomKeys(&rng, 12000);
  std::vector<Key> sorted = keys;
  std::sort(sorted.begin(), sorted.end());
  for (const std::vector<Key>* ks : {&keys, &sorted})
    for (const bool lattice : {false, true}) {
      NodeCache<double> a = lattice ? NodeCache<double>(3, 128) : NodeCache<double>();
      NodeCache<double> b = a;
      std::vector<double> vals(ks->size());
      for (std::size_t i = 0; i < ks->size(); ++i) {
        vals[i] = 0.25 * static_cast<double>(i);
        a.Set((*ks)[i], vals[i]);
      }
      b.SetMany(*ks, vals);
      ASSERT_EQ(a.SortedKeys(), b.SortedKeys());
      for (const Key k : a.SortedKeys()) EXPECT_EQ(*a.Lookup(k), *b.Lookup(k));
      for (const Key k : RandomKeys(&rng, 2000)) EXPECT_EQ(a.Lookup(k) == nullptr, b.Lookup(k) == nullptr);
      // Later values overwrite earlier ones in both.
      a.Set((*ks)[0], -1.0);
      b.SetMany({(*ks)[0]}, {-1.0});
      EXPECT_EQ(*a.Lookup((*ks)[0]), -1.0);
      EXPECT_EQ(*b.Lookup((*ks)[0]), -1.0);
    }
}

TEST(SpsrKeys, BrickIndexMatchesSortedList) {
  std::mt19937 rng(13);
  const std::vector<Key> keys = RandomKeys(&rng, 12000);
  std::set<Key> ref(keys.begin(), keys.end());
  const std::vector<Key> sorted(ref.begin(), ref.end());
  const BrickIndex index = BrickIndex::IndexOf(sorted);
  for (std::size_t i = 0; i < sorted.size(); ++i) EXPECT_EQ(index.Find(sorted[i]), static_cast<int>(i));
  int absent = 0;
  for (const Key k : RandomKeys(&rng, 3000)) {
    if (ref.count(k)) continue;
    EXPECT_EQ(index.Find(k), -1);
    ++absent;
  }
  EXPECT_GT(absent, 100);
}

// The sorted-set helpers against std::set built key by key: the union,
// the 3 x 3 x 3 dilation clipped to the grid (cells at the grid's faces
// included), and the cells' corners.
TEST(SpsrKeys, SortedSetHelpersMatchStdSet) {
  std::mt19937 rng(19);
  constexpr int kRes = 1024;
  std::vector<Key> a = RandomKeys(&rng, 9000), b = RandomKeys(&rng, 7000);
  for (int x = 0; x < 3; ++x)  // cells at the grid's low and high faces
    for (int y = 0; y < 2; ++y) {
      a.push_back(Pack(x, y, 0));
      a.push_back(Pack(kRes - 1 - x, kRes - 1, kRes - 1 - y));
    }
  std::vector<Key> sa = a, sb = b;
  SortUnique(sa);
  SortUnique(sb);
  const std::set<Key> ra(a.begin(), a.end()), rb(b.begin(), b.end());
  EXPECT_EQ(sa, std::vector<Key>(ra.begin(), ra.end()));
  std::set<Key> ru = ra;
  ru.insert(rb.begin(), rb.end());
  EXPECT_EQ(Union(sa, sb), std::vector<Key>(ru.begin(), ru.end()));
  std::set<Key> dilated, corners;
  for (const Key k : ra) {
    const int x = KX(k), y = KY(k), z = KZ(k);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int p = x + dx, q = y + dy, r = z + dz;
          if (p >= 0 && q >= 0 && r >= 0 && p < kRes && q < kRes && r < kRes) dilated.insert(Pack(p, q, r));
        }
    for (int c = 0; c < 8; ++c) corners.insert(Pack(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1)));
  }
  EXPECT_EQ(DilateCells(sa, kRes), std::vector<Key>(dilated.begin(), dilated.end()));
  EXPECT_EQ(CellCorners(sa), std::vector<Key>(corners.begin(), corners.end()));
  EXPECT_TRUE(DilateCells({}, kRes).empty());
  EXPECT_EQ(DilateCells({Pack(0, 0, 0)}, 1), std::vector<Key>{Pack(0, 0, 0)});  // a one-cell grid
}

// Checks 27-neighbour rows (rows[27 i + o] for queries[i]) against Find,
// -1 outside [0, res]^3; returns how many neighbours were found.
int ExpectRowsMatchFind(const BrickIndex& index, const std::vector<Key>& queries, const std::vector<int>& rows,
                        int res) {
  int found = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const int x = KX(queries[i]), y = KY(queries[i]), z = KZ(queries[i]);
    for (int o = 0; o < 27; ++o) {
      const int a = x + o % 3 - 1, b = y + (o / 3) % 3 - 1, c = z + o / 9 - 1;
      const bool inside = a >= 0 && b >= 0 && c >= 0 && a <= res && b <= res && c <= res;
      EXPECT_EQ(rows[i * 27 + o], inside ? index.Find(Pack(a, b, c)) : -1)
          << "query " << x << " " << y << " " << z << " o " << o;
      found += rows[i * 27 + o] >= 0;
    }
  }
  return found;
}

// NeighbourRows(Of) give what 27 calls of Find give, -1 outside [0, res]^3,
// for the list's nodes at the cube's faces too, the same rows whatever the
// blocks they are called on (the octree calls them on parallel blocks), and
// for queries that are not nodes.
TEST(SpsrKeys, NeighbourRowsMatchFind) {
  std::mt19937 rng(17);
  std::vector<Key> keys = RandomKeys(&rng, 12000);
  for (int a = 0; a <= 1; ++a)  // corner patches, so faces and corners are met
    for (int b = 0; b <= 2; ++b)
      for (int c = 0; c <= 3; ++c) {
        keys.push_back(Pack(a, b, c));
        keys.push_back(Pack(1023 - a, 1023 - b, 1023 - c));
      }
  const std::set<Key> ref(keys.begin(), keys.end());
  const std::vector<Key> sorted(ref.begin(), ref.end());
  const BrickIndex index = BrickIndex::IndexOf(sorted);
  constexpr int kRes = 1023;
  std::vector<int> whole(sorted.size() * 27), blocks(sorted.size() * 27);
  NeighbourRows(sorted, kRes, 0, sorted.size(), whole.data());
  for (std::size_t b = 0; b < sorted.size(); b += 777)
    NeighbourRows(sorted, kRes, b, std::min(sorted.size(), b + 777), &blocks[b * 27]);
  EXPECT_EQ(whole, blocks);
  const int found = ExpectRowsMatchFind(index, sorted, whole, kRes);
  // Each node finds itself; the check must also meet neighbours that exist.
  EXPECT_GT(found, static_cast<int>(sorted.size()) + 1000);
  // Queries that need not be nodes (the octree asks for the finer nodes
  // around (2x, 2y, 2z)): sorted, some in the list, some not.
  std::vector<Key> queries = RandomKeys(&rng, 4000);
  for (std::size_t i = 0; i < sorted.size(); i += 5) queries.push_back(sorted[i]);
  queries.push_back(Pack(0, 0, 0));
  queries.push_back(Pack(kRes, kRes, kRes));
  const std::set<Key> qs(queries.begin(), queries.end());
  queries.assign(qs.begin(), qs.end());
  std::vector<int> got(queries.size() * 27);
  NeighbourRowsOf(sorted, kRes, queries.data(), queries.size(), got.data());
  EXPECT_GT(ExpectRowsMatchFind(index, queries, got, kRes), 1000);
}

}  // namespace
}  // namespace arcs::spsr_keys
