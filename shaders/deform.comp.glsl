#version 430 core
// The deformation phase on the GPU (render/gpu_deformer.h): applies the binding table
// (core/binding.h) to the rest skin with the per-change maps core/deformer.cpp builds from the posed
// cage, and writes the deformed positions straight into the vertex buffer that is drawn. The
// arithmetic is Deformer::deform's, in the same float32 order. One invocation per skin point.
// The program is built five times with one of:
//   KERNEL_AFFINE        basic and extended variants: blend the 3x4 maps of the point's entries, apply once
//   KERNEL_RIGID         clamped variant: each entry's rigid map plus its anchor, blended
//   KERNEL_DENSE_AFFINE  the same two from the compact table (core/deform/kernel_table.h) the CPU reads
//   KERNEL_DENSE_RIGID   (groups of 8 points; each group's maps once, one unorm16 weight per point)
//   KERNEL_FALLBACK      points whose contributing set is empty follow one element rigidly
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer RestSkin { float rest_skin[]; };  // #P x 3
layout(std430, binding = 7) writeonly buffer Deformed { float deformed[]; };  // #P x 3, the drawn buffer

uniform vec3 u_origin;  // Binding::origin: maps act on positions relative to it
uniform uint u_count;   // invocations that do work: points, or fallback points
uniform uint u_row;     // invocations per row of the dispatch grid (large skins use a 2-D grid)

uint invocation() { return gl_GlobalInvocationID.y * u_row + gl_GlobalInvocationID.x; }

vec3 rest_at(uint i) {
  return vec3(rest_skin[3u * i] - u_origin.x, rest_skin[3u * i + 1u] - u_origin.y, rest_skin[3u * i + 2u] - u_origin.z);
}

void store(uint i, vec3 p) {
  deformed[3u * i] = p.x + u_origin.x;
  deformed[3u * i + 1u] = p.y + u_origin.y;
  deformed[3u * i + 2u] = p.z + u_origin.z;
}

#if defined(KERNEL_RIGID) || defined(KERNEL_FALLBACK) || defined(KERNEL_DENSE_RIGID)
// RigidMap (core/deformer.h), 20 floats: g (3x3 row-major), q0, d1, d2, padding
layout(std430, binding = 5) readonly buffer RigidMaps { float rigid[]; };  // #E x 20

vec3 apply_rigid(uint element, float b1, float b2, vec3 p) {
  uint o = 20u * element;
  vec3 y;
  for (uint k = 0u; k < 3u; ++k)
    y[k] = rigid[o + 3u * k] * p.x + rigid[o + 3u * k + 1u] * p.y + rigid[o + 3u * k + 2u] * p.z + rigid[o + 9u + k] +
           b1 * rigid[o + 12u + k] + b2 * rigid[o + 15u + k];
  return y;
}
#endif

#if defined(KERNEL_AFFINE) || defined(KERNEL_RIGID)
layout(std430, binding = 1) readonly buffer Offsets { uint offsets[]; };  // #P + 1
layout(std430, binding = 2) readonly buffer Ids { uint ids[]; };          // #entries
layout(std430, binding = 3) readonly buffer Weights { float weights[]; };  // #entries
#endif

#if defined(KERNEL_AFFINE)
// Affine (core/deformer.h): rows (m0 m1 m2 t) of y = M x + t, then a padding row
layout(std430, binding = 4) readonly buffer AffineMaps { vec4 maps[]; };  // #maps x 4

void main() {
  uint i = invocation();
  if (i >= u_count) return;
  vec4 r0 = vec4(0.0), r1 = vec4(0.0), r2 = vec4(0.0);
  uint end = offsets[i + 1u];
  for (uint e = offsets[i]; e < end; ++e) {
    float w = weights[e];
    uint m = 4u * ids[e];
    r0 += w * maps[m];
    r1 += w * maps[m + 1u];
    r2 += w * maps[m + 2u];
  }
  vec3 p = rest_at(i);
  store(i, vec3(r0.x * p.x + r0.y * p.y + r0.z * p.z + r0.w, r1.x * p.x + r1.y * p.y + r1.z * p.z + r1.w,
                r2.x * p.x + r2.y * p.y + r2.z * p.z + r2.w));
}
#endif

#if defined(KERNEL_RIGID)
layout(std430, binding = 4) readonly buffer Anchors { float bary[]; };  // #entries x 2: (b1, b2)

void main() {
  uint i = invocation();
  if (i >= u_count) return;
  vec3 p = rest_at(i);
  vec3 acc = vec3(0.0);
  uint end = offsets[i + 1u];
  for (uint e = offsets[i]; e < end; ++e) acc += weights[e] * apply_rigid(ids[e], bary[2u * e], bary[2u * e + 1u], p);
  store(i, acc);
}
#endif

#if defined(KERNEL_DENSE_AFFINE) || defined(KERNEL_DENSE_RIGID)
// KernelTable: group g holds points 8g .. 8g + 7 and members group_start[g] .. group_start[g + 1] - 1;
// member m names map member_id(m) and gives lane l the weight of cell m * rows * 8 + l (rigid: also
// w b1, w b2 in rows 1 and 2)
layout(std430, binding = 1) readonly buffer GroupStart { uint group_start[]; };  // #groups + 1
layout(std430, binding = 2) readonly buffer MemberIds { uint member_ids[]; };    // 16-bit, two a word
layout(std430, binding = 3) readonly buffer LaneWeights { uint lane_weights[]; };  // top 16 bits, two a word
layout(std430, binding = 6) readonly buffer LaneWeightsLow { uint lane_weights_lo[]; };  // low 8 bits, four a word
const uint LANES = 8u;
const float WEIGHT_SCALE = 1.0 / 16777215.0;  // KernelTable::kScale: a weight of 1 is 2^24 - 1

uint member_id(uint m) { return (member_ids[m >> 1u] >> (16u * (m & 1u))) & 0xffffu; }
// the 24-bit weight of cell (m * rows + row) * 8 + lane
float lane_weight(uint cell) {
  return 256.0 * float((lane_weights[cell >> 1u] >> (16u * (cell & 1u))) & 0xffffu) +
         float((lane_weights_lo[cell >> 2u] >> (8u * (cell & 3u))) & 0xffu);
}
#endif

#if defined(KERNEL_DENSE_AFFINE)
layout(std430, binding = 4) readonly buffer AffineMaps { vec4 maps[]; };  // #maps x 4

void main() {
  uint i = invocation();
  if (i >= u_count) return;
  uint g = i / LANES, lane = i % LANES;
  vec4 r0 = vec4(0.0), r1 = vec4(0.0), r2 = vec4(0.0);
  uint end = group_start[g + 1u];
  for (uint m = group_start[g]; m < end; ++m) {
    float w = lane_weight(m * LANES + lane);
    uint a = 4u * member_id(m);
    r0 += w * maps[a];
    r1 += w * maps[a + 1u];
    r2 += w * maps[a + 2u];
  }
  vec3 p = rest_at(i);
  store(i, vec3(r0.x * p.x + r0.y * p.y + r0.z * p.z + r0.w, r1.x * p.x + r1.y * p.y + r1.z * p.z + r1.w,
                r2.x * p.x + r2.y * p.y + r2.z * p.z + r2.w) * WEIGHT_SCALE);
}
#endif

#if defined(KERNEL_DENSE_RIGID)
void main() {
  uint i = invocation();
  if (i >= u_count) return;
  uint g = i / LANES, lane = i % LANES;
  vec3 g0 = vec3(0.0), g1 = vec3(0.0), g2 = vec3(0.0), q = vec3(0.0);  // blended rotation rows, anchor terms
  uint end = group_start[g + 1u];
  for (uint m = group_start[g]; m < end; ++m) {
    uint base = m * 3u * LANES + lane;
    float w = lane_weight(base), wb1 = lane_weight(base + LANES), wb2 = lane_weight(base + 2u * LANES);
    uint o = 20u * member_id(m);
    g0 += w * vec3(rigid[o], rigid[o + 1u], rigid[o + 2u]);
    g1 += w * vec3(rigid[o + 3u], rigid[o + 4u], rigid[o + 5u]);
    g2 += w * vec3(rigid[o + 6u], rigid[o + 7u], rigid[o + 8u]);
    q += w * vec3(rigid[o + 9u], rigid[o + 10u], rigid[o + 11u]) + wb1 * vec3(rigid[o + 12u], rigid[o + 13u], rigid[o + 14u]) +
         wb2 * vec3(rigid[o + 15u], rigid[o + 16u], rigid[o + 17u]);
  }
  vec3 p = rest_at(i);
  store(i, (vec3(dot(g0, p), dot(g1, p), dot(g2, p)) + q) * WEIGHT_SCALE);
}
#endif

#if defined(KERNEL_FALLBACK)
// one per fallback point: (point, element, b1 bits, b2 bits)
layout(std430, binding = 1) readonly buffer Fallback { uvec4 fallback[]; };

void main() {
  uint k = invocation();
  if (k >= u_count) return;
  uvec4 f = fallback[k];
  store(f.x, apply_rigid(f.y, uintBitsToFloat(f.z), uintBitsToFloat(f.w), rest_at(f.x)));
}
#endif
