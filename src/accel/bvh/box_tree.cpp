// The tree over boxes: its build, and its walks on lanes. A kernel file: compiled once per instruction
// set (src/core/isa_dispatch.hpp).

#include "visfield/accel/box_tree.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <string>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "bvh/binary_builder.hpp"
#include "bvh/box_test.hpp"
#include "bvh/collapse.hpp"
#include "bvh/wide_traversal.hpp"
#include "core/isa_dispatch.hpp"
#include "visfield/accel/aligned_vector.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/lane_compress.hpp"
#include "visfield/core/row_transpose.hpp"

namespace vf::isa_avx512 {
void box_tree_items_met(const BoxTree& tree, const Ray& ray, std::vector<std::uint32_t>& items);
int box_tree_batch_width(int width);
void box_tree_rays_by_item(const BoxTree& tree, std::span<const Ray> rays, const std::uint8_t* skip, ItemRays& out, int width);
void box_tree_visit_leaves(const BoxTree& tree, std::span<const Ray> rays, const std::uint8_t* skip, const BoxTree::LeafVisitor& visit,
                           int width);
}  // namespace vf::isa_avx512

namespace vf {

struct BoxTree::Layout {
  AlignedVector<bvh::Node8> nodes;  // nodes[0] the root whenever there is an item
  std::vector<std::uint32_t> items;  // item indices in leaf order
};

BoxTree::BoxTree() = default;
BoxTree::BoxTree(BoxTree&&) noexcept = default;
BoxTree& BoxTree::operator=(BoxTree&&) noexcept = default;
BoxTree::~BoxTree() = default;

BoxTree BoxTree::build(std::span<const Bounds3f> boxes, int leaf_items) {
  if (leaf_items < 1 || leaf_items > 128) throw Error("box tree: leaf_items must be in [1, 128], got " + std::to_string(leaf_items));
  BoxTree tree;
  tree.layout_ = std::make_unique<Layout>();
  std::vector<std::uint32_t> kept;
  std::vector<Bounds3f> kept_boxes;
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    if (boxes[k].empty()) continue;
    kept.push_back(static_cast<std::uint32_t>(k));
    kept_boxes.push_back(boxes[k]);
  }
  if (kept.empty()) return tree;
  BvhConfig config;
  config.max_leaf_size = leaf_items;
  const bvh::BinaryTree binary = bvh::build_binary_tree(kept_boxes, config, leaf_items);
  AccelStats stats;
  Layout& l = *tree.layout_;
  bvh::collapse_to_wide(binary, l.nodes, stats, [&](const bvh::BinaryNode& leaf) {
    const auto first = static_cast<std::uint32_t>(l.items.size());
    for (std::uint32_t j = 0; j < leaf.count; ++j) l.items.push_back(kept[binary.order[leaf.begin + j]]);
    return bvh::leaf_ref(first, leaf.count);
  });
  return tree;
}

void BoxTree::items_met(const Ray& ray, std::vector<std::uint32_t>& items) const {
  VF_USE_WIDER(box_tree_items_met, *this, ray, items);
  if (!layout_ || layout_->nodes.empty() || !ray.is_valid()) return;
  const float inv[3] = {bvh::box_reciprocal(ray.dir.x), bvh::box_reciprocal(ray.dir.y), bvh::box_reciprocal(ray.dir.z)};
  bvh::BoxRay box;
  box.set(ray, inv);
  const std::uint32_t* order = layout_->items.data();
  bvh::any_hit_walk(layout_->nodes.data(), box, ray.tmin, ray.tmax, [&](std::uint32_t ref) {
    const std::uint32_t first = bvh::leaf_first_item(ref), count = bvh::leaf_item_count(ref);
    items.insert(items.end(), order + first, order + first + count);
    return false;  // every item met, not the first
  });
}

namespace {

// A node's rays go to its children in one of two ways, with the same pairs (the walk's box test,
// the same operations on the same values) and the same lists:
// - by rows: a ray at a time against the node's eight boxes (the walk's test as it is), each ray
//   read through its index; any build;
// - by columns (AVX-512): sixteen rays at a time against one box, the rays' values held in columns
//   that move down the tree with them, so that a node reads its rays in order and a child gets
//   its rays by a permute a column (1024 bunnies' AO rays, the whole field query: 23.6-23.8
//   Mrays/s by rows, 25.0-25.4 by columns, four interleaved rounds).

/// A node's rays, places begin .. begin + count of its region (a listed leaf's: of out.rays; an
/// interior node's, and a visited leaf's: of the split's ids and columns): pending until the node is
/// taken. `mark`: where a
/// split's scratch may start again once this node is taken (the columns split's; what lies above
/// it belongs to subtrees already taken).
struct Pending {
  std::uint32_t ref, begin, count, mark = 0;
};

/// The value of `size` a growing buffer is given when it must hold `need`: doubled, so that a
/// block's growth costs O(final size).
std::size_t grown(std::size_t size, std::size_t need) { return std::max(need, 2 * size); }

/// Takes the tree's nodes from the root's `count` rays down: `split(node, p, pending)` hands an
/// interior node's rays to its children, pushing a Pending for each child that gets some, last to
/// first (so that children are taken in tree order); `leaf(p)` takes a leaf's. The root's rays are at
/// 0 .. count, its mark `mark`.
template <class Split, class Leaf>
void down_the_tree(const bvh::Node8* nodes, std::uint32_t count, std::uint32_t mark, Split&& split, Leaf&& leaf) {
  std::vector<Pending> pending{{bvh::node_ref(0), 0, count, mark}};
  while (!pending.empty()) {
    const Pending p = pending.back();
    pending.pop_back();
    if (bvh::is_leaf(p.ref))
      leaf(p);
    else
      split(bvh::node_at(nodes, p.ref), p, pending);
  }
}

/// A leaf's rays (places p.begin .. of out.rays) become each of its items' list.
void add_lists(const std::uint32_t* order, const Pending& p, ItemRays& out) {
  const std::uint32_t first = bvh::leaf_first_item(p.ref), items = bvh::leaf_item_count(p.ref);
  for (std::uint32_t k = 0; k < items; ++k) out.lists.push_back({order[first + k], p.begin, p.count});
}

/// kSpread[b]: bit k of b moved to byte k (a child's count in a byte of one word).
constexpr std::array<std::uint64_t, 256> kSpread = [] {
  std::array<std::uint64_t, 256> spread{};
  for (unsigned b = 0; b < 256; ++b)
    for (int k = 0; k < 8; ++k) spread[b] |= static_cast<std::uint64_t>((b >> k) & 1u) << (8 * k);
  return spread;
}();

void partition_by_rows(const bvh::Node8* nodes, const std::uint32_t* order, std::span<const Ray> rays, const std::uint8_t* skip,
                       ItemRays& out) {
  // What a node's box test needs of each ray, made once: every node a ray reaches reads it again.
  struct RayConstants {
    float org[3], inv[3];
    float tmin, tmax;  // widened as a walk's
  };
  thread_local std::vector<RayConstants> constants;
  thread_local std::vector<std::uint8_t> lanes_of;
  constants.resize(rays.size());
  // out.rays only grows (its size is room, not content: growing it zeroes what it adds).
  std::size_t used = 0;
  const auto room = [&](std::size_t need) {
    if (out.rays.size() < need) out.rays.resize(grown(out.rays.size(), need));
  };
  room(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (skip && skip[i]) continue;
    const Ray& ray = rays[i];
    RayConstants& c = constants[i];
    for (int a = 0; a < 3; ++a) {
      c.org[a] = ray.org[a];
      c.inv[a] = bvh::box_reciprocal(ray.dir[a]);
    }
    c.tmin = bvh::widen_down(ray.tmin);
    c.tmax = bvh::widen_up(ray.tmax);
    out.rays[used++] = static_cast<std::uint32_t>(i);
  }
  if (used == 0) return;
  const auto split = [&](const bvh::Node8& node, const Pending& p, std::vector<Pending>& pending) {
    // The children each ray meets, and how many rays each gets.
    if (lanes_of.size() < p.count) lanes_of.resize(p.count);
    std::uint32_t met[8] = {};
    // Counted a byte a child in one word (kSpread), emptied into met before a byte can overflow.
    std::uint64_t counts = 0;
    int in_counts = 0;
    // Plain pointers: the byte stores below could alias the vectors' own, which the loop would reload.
    const RayConstants* const constant = constants.data();
    const std::uint32_t* const rays_here = out.rays.data() + p.begin;
    std::uint8_t* const lanes_here = lanes_of.data();
    for (std::uint32_t j = 0; j < p.count; ++j) {
      const RayConstants& c = constant[rays_here[j]];
      bvh::BoxRay box;
      box.set(c.org, c.inv);
      bvh::V8 unused;
      const simd::LaneBits lanes = bvh::test_children(node, box, bvh::V8::broadcast(c.tmin), bvh::V8::broadcast(c.tmax), unused);
      lanes_here[j] = static_cast<std::uint8_t>(lanes);
      counts += kSpread[lanes];
      if (++in_counts == 255 || j + 1 == p.count) {
        in_counts = 0;
        for (int child = 0; child < 8; ++child) met[child] += static_cast<std::uint32_t>((counts >> (8 * child)) & 255u);
        counts = 0;
      }
    }
    // Each child's rays after the others' (a slot to spare each, for the stores of the rays that
    // miss it), in order: every ray stored at its child's cursor, which moves on where it meets it.
    std::uint32_t cursor[8];
    for (int child = 0; child < 8; ++child) {
      cursor[child] = static_cast<std::uint32_t>(used);
      used += met[child] + 1;
    }
    room(used);
    std::uint32_t* stored = out.rays.data();
    for (std::uint32_t j = 0; j < p.count; ++j) {
      const std::uint32_t ray = stored[p.begin + j], lanes = lanes_here[j];
      for (int child = 0; child < 8; ++child) {
        stored[cursor[child]] = ray;
        cursor[child] += (lanes >> child) & 1u;
      }
    }
    for (int child = 7; child >= 0; --child)
      if (met[child] > 0) pending.push_back({node.child[child], cursor[child] - met[child], met[child]});
  };
  down_the_tree(nodes, static_cast<std::uint32_t>(used), 0, split, [&](const Pending& p) { add_lists(order, p, out); });
}

#if defined(__AVX2__)
/// The lanes of the columns walk, as one small interface over AVX-512 (16) and AVX2 (8): a lane set
/// is a bit mask (bit i = lane i); ids and lane numbers are 32-bit integer lanes.
#if defined(__AVX512F__) && defined(__AVX512DQ__)
struct ColumnLanes16 {
  static constexpr int kLanes = 16;
  using Mask = std::uint32_t;
  using Float = __m512;
  using Int = __m512i;
  using BoxRays = bvh::BoxRays16;
  static constexpr Mask kAll = 0xffff;

  static Mask first_lanes(std::size_t n) { return n >= kLanes ? kAll : (1u << n) - 1u; }
  static Float zero() { return _mm512_setzero_ps(); }
  static Float load(const float* p) { return _mm512_loadu_ps(p); }
  static Int load(const std::uint32_t* p) { return _mm512_loadu_si512(p); }
  static void store(float* p, Float v) { _mm512_storeu_ps(p, v); }
  static void store(std::uint32_t* p, Int v) { _mm512_storeu_si512(p, v); }
  static Int iota() { return _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15); }
  /// first, first + 1, ... in lane order.
  static Int indices_from(std::uint32_t first) { return _mm512_add_epi32(_mm512_set1_epi32(static_cast<int>(first)), iota()); }
  /// The numbers of the lanes in `m`, in order, in the first lanes.
  static Int compress_index(Mask m) { return _mm512_maskz_compress_epi32(static_cast<__mmask16>(m), iota()); }
  /// Lane k gets v's lane from[k] (the zero-masking forms with every lane kept: GCC 12's plain forms
  /// trip its own uninitialised-value warning).
  static Float permute(Int from, Float v) { return _mm512_maskz_permutexvar_ps(0xffff, from, v); }
  static Int permute(Int from, Int v) { return _mm512_maskz_permutexvar_epi32(0xffff, from, v); }
  /// v's lanes in `m`, in order, in the first lanes.
  static Int compress(Mask m, Int v) { return _mm512_maskz_compress_epi32(static_cast<__mmask16>(m), v); }
  static void rows_to_columns(const float* rows, Float column[8]) { simd::rows_to_columns16(rows, column); }
  /// The lanes whose byte at p is zero.
  static Mask zero_bytes(const std::uint8_t* p) {
    const __m512i bytes = _mm512_maskz_cvtepu8_epi32(0xffff, _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
    return _mm512_testn_epi32_mask(bytes, bytes);
  }
  /// The lanes of `valid` whose bits at p differ from `value`'s.
  static Mask differ(Mask valid, const float* p, float value) {
    return _mm512_mask_cmpneq_epi32_mask(static_cast<__mmask16>(valid), _mm512_loadu_si512(p),
                                         _mm512_set1_epi32(std::bit_cast<std::int32_t>(value)));
  }
  /// The lanes of `live` whose ray (ids[lane]) has no skip byte set; `count` bytes of skip are readable.
  static Mask unsettled(const std::uint32_t* ids, Mask live, const std::uint8_t* skip, std::size_t count) {
    if (live == 0) return 0;
    const int last = 31 - std::countl_zero(live);
    if (std::size_t{ids[last]} + 4 <= count) {  // ascending ids: the last the largest; 4 bytes a lane read
      const __m512i settled =
          _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), static_cast<__mmask16>(live), _mm512_loadu_si512(ids), skip, 1);
      return _mm512_testn_epi32_mask(settled, _mm512_set1_epi32(0xff));
    }
    Mask open = 0;
    for (int lane = 0; lane <= last; ++lane) open |= (skip[ids[lane]] == 0 ? 1u : 0u) << lane;
    return open;
  }
  /// sum + v in the lanes of `m`, sum elsewhere.
  static Float add(Float sum, Mask m, Float v) { return _mm512_mask_add_ps(sum, static_cast<__mmask16>(m), sum, v); }
};
#endif

/// ColumnLanes16's operations on 8 AVX2 lanes: compresses by a permute, masks as bits.
struct ColumnLanes8 {
  static constexpr int kLanes = 8;
  using Mask = std::uint32_t;
  using Float = __m256;
  using Int = __m256i;
  using BoxRays = bvh::BoxRays8;
  static constexpr Mask kAll = 0xff;

  static Mask first_lanes(std::size_t n) { return n >= kLanes ? kAll : (1u << n) - 1u; }
  static Float zero() { return _mm256_setzero_ps(); }
  static Float load(const float* p) { return _mm256_loadu_ps(p); }
  static Int load(const std::uint32_t* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
  static void store(float* p, Float v) { _mm256_storeu_ps(p, v); }
  static void store(std::uint32_t* p, Int v) { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), v); }
  static Int indices_from(std::uint32_t first) {
    return _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(first)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  }
  static Int compress_index(Mask m) { return simd::compress_index8(m); }
  static Float permute(Int from, Float v) { return _mm256_permutevar8x32_ps(v, from); }
  static Int permute(Int from, Int v) { return _mm256_permutevar8x32_epi32(v, from); }
  static Int compress(Mask m, Int v) { return permute(compress_index(m), v); }
  static void rows_to_columns(const float* rows, Float column[8]) { simd::rows_to_columns8(rows, column); }
  static Mask zero_bytes(const std::uint8_t* p) {
    std::uint64_t eight;
    std::memcpy(&eight, p, sizeof(eight));
    const __m256i bytes = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(eight)));
    return static_cast<Mask>(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(bytes, _mm256_setzero_si256()))));
  }
  static Mask differ(Mask valid, const float* p, float value) {
    const __m256i equal = _mm256_cmpeq_epi32(load(reinterpret_cast<const std::uint32_t*>(p)), _mm256_set1_epi32(std::bit_cast<std::int32_t>(value)));
    return valid & ~static_cast<Mask>(_mm256_movemask_ps(_mm256_castsi256_ps(equal)));
  }
  // A lane at a time: AVX2's gather is slow on the AMD machines it was measured on.
  static Mask unsettled(const std::uint32_t* ids, Mask live, const std::uint8_t* skip, std::size_t) {
    Mask open = 0;
    for (Mask rest = live; rest != 0; rest &= rest - 1) {
      const int lane = std::countr_zero(rest);
      open |= (skip[ids[lane]] == 0 ? 1u : 0u) << lane;
    }
    return open;
  }
  static Float add(Float sum, Mask m, Float v) {
    const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const __m256i in = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(m)), bit), bit);
    return _mm256_add_ps(sum, _mm256_and_ps(v, _mm256_castsi256_ps(in)));
  }
};

/// The columns walk: with `out`, a leaf's rays become its items' lists (their ids alone); with `visit`
/// (and no `out`), a leaf's rays stay in the scratch as columns and visit takes them there. `L`: the
/// lanes (ColumnLanes16 or ColumnLanes8), the same lists and leaves either way.
template <class L>
void partition_by_columns(const bvh::Node8* nodes, const std::uint32_t* order, std::span<const Ray> rays, const std::uint8_t* skip,
                          ItemRays* out, const BoxTree::LeafVisitor* visit) {
  constexpr int kLanes = L::kLanes;
  using Mask = typename L::Mask;
  // Places every region has to spare: for whole-register stores, and for a visit's whole-register reads.
  constexpr std::size_t kSpare = std::max<std::size_t>(kLanes, BoxTree::LeafRays::kSlack);
  // An interior node's rays, in a scratch stack: columns (origin x, y, z, direction x, y, z, tmin and
  // tmax, the last two only where the block's rays differ in them) and ids. The directions, not their
  // reciprocals, go down: each node's load divides again (as the walk does, so the same bits), which
  // costs nothing measurable (1024 bunnies, 6 interleaved rounds: medians 4.54x both), and a leaf can
  // then hand on the rays themselves. A node taken from the pending stack finds every region above its
  // mark dead (its earlier siblings' subtrees are done), so the scratch is reused depth first and
  // stays in cache: growing it for every node instead touched 3.8 MB a block of 16384 rays on 1024
  // bunnies, 7.7 regions a ray. A leaf's rays become its items' lists, their ids alone in out->rays,
  // or stay in the scratch for `visit`.
  thread_local std::vector<float> columns[8];
  thread_local std::vector<std::uint32_t> ids;
  thread_local std::vector<std::uint16_t> masks;  // a node's: chunk k, child c at 8 k + c
  const auto scratch_room = [&](std::size_t need) {
    if (ids.size() >= need) return;
    const std::size_t size = grown(ids.size(), need);
    ids.resize(size);
    for (std::vector<float>& column : columns) column.resize(size);
  };
  const auto leaf_room = [&](std::size_t need) {
    if (out && out->rays.size() < need) out->rays.resize(grown(out->rays.size(), need));
  };
  scratch_room(rays.size() + kSpare);
  // The open rays into the columns, a register of rays at a time: read as rows and turned into columns, the
  // skipped ones left out by one compress of the lane numbers and a permute a column (a ray at a
  // time, its eight scalar stores and three divisions were a tenth of 1024 bunnies' AO time; ratio
  // to Embree's instancing, medians of six interleaved rounds, 3.89x -> 4.06x). The intervals go in
  // as given; they are widened below, by the walks' own scalar functions.
  std::size_t used = 0;
  {
    float* column[8];
    for (int k = 0; k < 8; ++k) column[k] = columns[k].data();
    std::uint32_t* const id = ids.data();
    const float* const row = reinterpret_cast<const float*>(rays.data());
    static_assert(sizeof(Ray) == 8 * sizeof(float), "a Ray is 8 floats: org, dir, tmin, tmax");
    std::size_t i = 0;
    for (; i + kLanes <= rays.size(); i += kLanes) {
      Mask open = L::kAll;
      if (skip) {
        open = L::zero_bytes(skip + i);
        if (open == 0) continue;
      }
      typename L::Float v[8];
      L::rows_to_columns(row + 8 * i, v);
      const typename L::Int from = L::compress_index(open);
      for (int k = 0; k < 8; ++k) L::store(column[k] + used, L::permute(from, v[k]));
      L::store(id + used, L::permute(from, L::indices_from(static_cast<std::uint32_t>(i))));
      used += static_cast<std::size_t>(std::popcount(open));
    }
    for (; i < rays.size(); ++i) {
      if (skip && skip[i]) continue;
      const Ray& ray = rays[i];
      for (int a = 0; a < 3; ++a) {
        column[a][used] = ray.org[a];
        column[3 + a][used] = ray.dir[a];
      }
      column[6][used] = ray.tmin;
      column[7][used] = ray.tmax;
      id[used++] = static_cast<std::uint32_t>(i);
    }
  }
  if (used == 0) return;
  const auto count = static_cast<std::uint32_t>(used);
  // A block whose rays share tmin and tmax (AO rays of one length, say) carries them as constants:
  // two columns fewer to move at every node (1024 bunnies, ratio to Embree's instancing, medians of
  // six interleaved rounds: 3.74x -> 3.97x). Otherwise every ray's interval goes down as given and is
  // widened at each node's load.
  // Compared as bits, a register at a time (a ray at a time, this loop was a twentieth of the walk).
  bool shared = true;
  for (std::size_t k = 0; k < used && shared; k += kLanes) {
    const Mask valid = L::first_lanes(used - k);
    shared = (L::differ(valid, columns[6].data() + k, columns[6][0]) | L::differ(valid, columns[7].data() + k, columns[7][0])) == 0;
  }
  const float tmin = bvh::widen_down(columns[6][0]), tmax = bvh::widen_up(columns[7][0]);
  // A visit's rays have their intervals as columns either way: the shared one in columns of its own.
  thread_local std::vector<float> shared_interval[2];
  if (visit && shared)
    for (int k = 0; k < 2; ++k) shared_interval[k].assign(used + BoxTree::LeafRays::kSlack, columns[6 + k][0]);
  // A visit may settle rays (skip[i] set) while the walk goes on: the lanes of a chunk whose rays are
  // still open, so that settled rays go no further down.
  std::size_t leaf_used = 0;
  // kCarried: the columns that move down the tree with the rays (6: tmin and tmax are constants).
  const auto walk = [&](auto carried) {
    constexpr int kCarried = decltype(carried)::value;
    const auto split = [&](const bvh::Node8& node, const Pending& p, std::vector<Pending>& pending) {
      std::size_t top = p.mark;
      int slots[8], children = 0;
      bool leaf[8];  // a leaf whose ids alone go to out->rays
      for (int slot = 0; slot < 8; ++slot) {
        leaf[slot] = out && bvh::is_leaf(node.child[slot]);
        if (node.bounds[bvh::kLoX][slot] <= node.bounds[bvh::kHiX][slot]) slots[children++] = slot;  // unused slots are empty boxes
      }
      const std::uint32_t chunks = (p.count + kLanes - 1) / kLanes;
      if (masks.size() < 8 * std::size_t{chunks}) masks.resize(8 * std::size_t{chunks});
      std::uint32_t met[8] = {};
      const float* column[8];
      for (int k = 0; k < 8; ++k) column[k] = columns[k].data() + p.begin;
      std::uint16_t* const node_masks = masks.data();
      typename L::Float origin_sum[3] = {L::zero(), L::zero(), L::zero()};
      int live_count = 0;
      for (std::uint32_t chunk = 0; chunk < chunks; ++chunk) {
        const std::uint32_t at = chunk * kLanes;
        Mask live = L::first_lanes(p.count - at);
        if (visit && skip) live &= L::unsettled(ids.data() + p.begin + at, live, skip, rays.size());
        typename L::BoxRays r;
        if constexpr (kCarried == 8) {
          r.load(column, at);
        } else {
          r.load(column, at, tmin, tmax);
        }
        if (visit) {
          for (int a = 0; a < 3; ++a) origin_sum[a] = L::add(origin_sum[a], live, r.org[a]);
          live_count += std::popcount(live);
        }
        for (int c = 0; c < children; ++c) {
          const int slot = slots[c];
          const Mask meets = bvh::rays_meet_child(node, slot, r) & live;
          node_masks[8 * std::size_t{chunk} + static_cast<std::size_t>(slot)] = static_cast<std::uint16_t>(meets);
          met[slot] += static_cast<std::uint32_t>(std::popcount(meets));
        }
      }
      // Each child's rays after the others', moved out of each chunk, column by column: an interior
      // child's into the scratch above this node's mark, a leaf's ids into out.rays.
      std::uint32_t cursor[8];
      for (int c = 0; c < children; ++c) {
        std::size_t& end = leaf[slots[c]] ? leaf_used : top;
        cursor[slots[c]] = static_cast<std::uint32_t>(end);
        end += met[slots[c]] + kSpare;
      }
      scratch_room(top);
      leaf_room(leaf_used);
      // Plain pointers, after the rooms: the stores below could alias the vectors' own.
      float* base[8];
      for (int k = 0; k < 8; ++k) base[k] = columns[k].data();
      std::uint32_t* const id_base = ids.data();
      std::uint32_t* const leaf_ids = out ? out->rays.data() : nullptr;
      const std::uint16_t* const mask = masks.data();
      for (std::uint32_t chunk = 0; chunk < chunks; ++chunk) {
        const std::uint32_t at = p.begin + chunk * kLanes;
        typename L::Float v[kCarried];
        for (int k = 0; k < kCarried; ++k) v[k] = L::load(base[k] + at);
        const typename L::Int id = L::load(id_base + at);
        for (int c = 0; c < children; ++c) {
          const int slot = slots[c];
          const Mask meets = mask[8 * std::size_t{chunk} + static_cast<std::size_t>(slot)];
          if (meets == 0) continue;
          const std::uint32_t to = cursor[slot];
          // A leaf's rays become its items' lists: their ids alone go on (1024 bunnies' AO rays, the
          // whole field query: 35.1-38.3 -> 38.4-40.1 Mrays/s, four interleaved rounds).
          if (leaf[slot]) {
            L::store(leaf_ids + to, L::compress(meets, id));
          } else {
            // The compress made once, on lane numbers, and applied to each column by a permute: one
            // micro-op a column where an AVX-512 compress takes two (1024 bunnies, ratio to Embree's
            // instancing, medians of six interleaved rounds: 3.97x -> 4.14x).
            const typename L::Int from = L::compress_index(meets);
            for (int k = 0; k < kCarried; ++k) L::store(base[k] + to, L::permute(from, v[k]));
            L::store(id_base + to, L::permute(from, id));
          }
          cursor[slot] = to + static_cast<std::uint32_t>(std::popcount(meets));
        }
      }
      if (visit) {
        // The children nearest the mean origin of this node's open rays are taken first: their objects
        // settle the rays they occlude (an AO ray's own object and its neighbours) before the walk takes
        // those rays to farther subtrees. 1024 bunnies' AO: 2% fewer pairs, 17% fewer nodes with rays
        // to test; ratio to Embree's instancing, 5 interleaved rounds: medians 4.70x -> 4.79x, busts
        // 4.97x -> 5.16x.
        float mean[3];
        for (int a = 0; a < 3; ++a) {
          alignas(64) float lanes[kLanes];
          L::store(lanes, origin_sum[a]);
          mean[a] = 0.0f;
          for (const float lane : lanes) mean[a] += lane;
        }
        float distance[8];
        for (int c = 0; c < children; ++c) {
          const int slot = slots[c];
          float d = 0.0f;
          for (int a = 0; a < 3; ++a) {
            const float x = mean[a] / static_cast<float>(std::max(live_count, 1));
            const float gap = std::max({node.bounds[bvh::kLoX + a][slot] - x, x - node.bounds[bvh::kHiX + a][slot], 0.0f});
            d += gap * gap;
          }
          distance[slot] = d;
        }
        std::sort(slots, slots + children, [&](int a, int b) { return distance[a] > distance[b]; });
        for (int c = 0; c < children; ++c) {
          const int slot = slots[c];
          if (met[slot] > 0) pending.push_back({node.child[slot], cursor[slot] - met[slot], met[slot], static_cast<std::uint32_t>(top)});
        }
        return;
      }
      for (int c = children - 1; c >= 0; --c) {
        const int slot = slots[c];
        if (met[slot] > 0) pending.push_back({node.child[slot], cursor[slot] - met[slot], met[slot], static_cast<std::uint32_t>(top)});
      }
    };
    down_the_tree(nodes, count, static_cast<std::uint32_t>(count + kSpare), split, [&](const Pending& p) {
      if (out) {
        add_lists(order, p, *out);
        return;
      }
      BoxTree::LeafRays leaf;
      leaf.items = {order + bvh::leaf_first_item(p.ref), bvh::leaf_item_count(p.ref)};
      for (int k = 0; k < 8; ++k) leaf.columns[k] = columns[k].data() + p.begin;
      if constexpr (kCarried == 6) {
        leaf.columns[6] = shared_interval[0].data();
        leaf.columns[7] = shared_interval[1].data();
      }
      leaf.ids = ids.data() + p.begin;
      leaf.count = p.count;
      (*visit)(leaf);
    });
  };
  if (shared) {
    walk(std::integral_constant<int, 6>{});
  } else {
    walk(std::integral_constant<int, 8>{});
  }
}
#endif

}  // namespace

int BoxTree::batch_width(int width) {
  VF_USE_WIDER(box_tree_batch_width, width);
#if defined(__AVX512F__) && defined(__AVX512DQ__)
  constexpr int widest = 16;
#elif defined(__AVX2__)
  constexpr int widest = 8;
#else
  constexpr int widest = 1;
#endif
  if (width <= 0 || width > widest) return widest;
  return width >= 16 ? 16 : width >= 8 ? 8 : 1;
}

void BoxTree::rays_by_item(std::span<const Ray> rays, const std::uint8_t* skip, ItemRays& out, int width) const {
  VF_USE_WIDER(box_tree_rays_by_item, *this, rays, skip, out, width);
  out.lists.clear();
  if (!layout_ || layout_->nodes.empty()) return;
#if defined(__AVX512F__) && defined(__AVX512DQ__)
  if (batch_width(width) == 16) {
    partition_by_columns<ColumnLanes16>(layout_->nodes.data(), layout_->items.data(), rays, skip, &out, nullptr);
    return;
  }
#endif
#if defined(__AVX2__)
  if (batch_width(width) == 8) {
    partition_by_columns<ColumnLanes8>(layout_->nodes.data(), layout_->items.data(), rays, skip, &out, nullptr);
    return;
  }
#endif
  (void)width;
  partition_by_rows(layout_->nodes.data(), layout_->items.data(), rays, skip, out);
}

void BoxTree::visit_leaves(std::span<const Ray> rays, const std::uint8_t* skip, const LeafVisitor& visit, int width) const {
  VF_USE_WIDER(box_tree_visit_leaves, *this, rays, skip, visit, width);
  if (!layout_ || layout_->nodes.empty()) return;
#if defined(__AVX512F__) && defined(__AVX512DQ__)
  if (batch_width(width) == 16) {
    partition_by_columns<ColumnLanes16>(layout_->nodes.data(), layout_->items.data(), rays, skip, nullptr, &visit);
    return;
  }
#endif
#if defined(__AVX2__)
  if (batch_width(width) == 8) {
    partition_by_columns<ColumnLanes8>(layout_->nodes.data(), layout_->items.data(), rays, skip, nullptr, &visit);
    return;
  }
#endif
  (void)width;
  // A ray at a time: the lists, then each leaf's rays still open copied into columns (a leaf's lists
  // come side by side and share their rays).
  thread_local ItemRays by_item;
  thread_local std::array<std::vector<float>, 8> columns;
  thread_local std::vector<std::uint32_t> ids;
  by_item.lists.clear();
  partition_by_rows(layout_->nodes.data(), layout_->items.data(), rays, skip, by_item);
  for (std::size_t at = 0, end = 0; at < by_item.lists.size(); at = end) {
    const ItemRays::List& list = by_item.lists[at];
    end = at + 1;
    while (end < by_item.lists.size() && by_item.lists[end].begin == list.begin) ++end;
    thread_local std::vector<std::uint32_t> items;
    items.clear();
    for (std::size_t k = at; k < end; ++k) items.push_back(by_item.lists[k].item);
    for (std::vector<float>& column : columns) column.assign(list.count + LeafRays::kSlack, 0.0f);
    ids.assign(list.count + LeafRays::kSlack, 0);
    std::size_t open = 0;
    for (std::uint32_t k = 0; k < list.count; ++k) {
      const std::uint32_t i = by_item.rays[list.begin + k];
      if (skip && skip[i]) continue;
      const Ray& ray = rays[i];
      const float values[8] = {ray.org.x, ray.org.y, ray.org.z, ray.dir.x, ray.dir.y, ray.dir.z, ray.tmin, ray.tmax};
      for (int c = 0; c < 8; ++c) columns[c][open] = values[c];
      ids[open++] = i;
    }
    if (open == 0) continue;
    LeafRays leaf;
    leaf.items = items;
    for (int c = 0; c < 8; ++c) leaf.columns[c] = columns[c].data();
    leaf.ids = ids.data();
    leaf.count = open;
    visit(leaf);
  }
}

std::size_t BoxTree::memory_bytes() const {
  return layout_ ? layout_->nodes.capacity() * sizeof(bvh::Node8) + layout_->items.capacity() * sizeof(std::uint32_t) : 0;
}

}  // namespace vf

#if VF_IN_WIDER_COPY
namespace vf::isa_avx512 {
VF_WIDER_ENTRY void box_tree_items_met(const BoxTree& tree, const Ray& ray, std::vector<std::uint32_t>& items) { tree.items_met(ray, items); }
VF_WIDER_ENTRY int box_tree_batch_width(int width) { return BoxTree::batch_width(width); }
VF_WIDER_ENTRY void box_tree_rays_by_item(const BoxTree& tree, std::span<const Ray> rays, const std::uint8_t* skip, ItemRays& out, int width) {
  tree.rays_by_item(rays, skip, out, width);
}
VF_WIDER_ENTRY void box_tree_visit_leaves(const BoxTree& tree, std::span<const Ray> rays, const std::uint8_t* skip,
                                          const BoxTree::LeafVisitor& visit, int width) {
  tree.visit_leaves(rays, skip, visit, width);
}
}  // namespace vf::isa_avx512
#endif
