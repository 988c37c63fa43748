#version 430 core
// A stack of deformers on one skin on the GPU (render/gpu_deformer.h GpuStack, docs/deformer-stack.md):
// core/rig/deformer_stack.cpp combine_stack's arithmetic per skin point, in float32 where the CPU
// computes in double. The skin buffer holds f_0 (the document's cage's skin, or the rest skin when it
// is muted) and receives the combined skin; each layer's posed skin is a slice of one table, written
// there by its own deform pass. A layer may instead be a parametric driver's displacement (uploaded from
// the CPU, core/rig/driver_layer.h): it is added, scaled by its mask, where it sits (in order and sum), or
// to the blended skin (blend), as combine_layers does. One invocation per skin point.
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer RestSkin { float rest_skin[]; };    // #P x 3
layout(std430, binding = 1) readonly buffer Layers { float layer_skins[]; };   // #L slices of u_stride floats, #P x 3 each
layout(std430, binding = 2) readonly buffer Masks { float masks[]; };          // the masks of the layers that have one, #P each
// #L: where layer k's mask starts, or kNoMask; then #L: 1 when layer k is a displacement, else 0
layout(std430, binding = 3) readonly buffer MaskStarts { uint mask_start[]; };
layout(std430, binding = 7) buffer Skin { float skin[]; };                     // #P x 3: f_0 in, the combined skin out

const uint kNoMask = 0xffffffffu;  // a layer without a mask moves every point fully
const uint kInOrder = 0u, kSum = 1u, kBlend = 2u;  // core/document/document.h StackMode

uniform uint u_count;     // skin points
uniform uint u_row;       // invocations per row of the dispatch grid (large skins use a 2-D grid)
uniform uint u_layers;    // #L
uniform uint u_stride;    // floats from one layer's slice to the next (the storage offset alignment)
uniform uint u_mode;      // kInOrder, kSum or kBlend
uniform float u_exponent; // kBlend's m (>= 0)

uint invocation() { return gl_GlobalInvocationID.y * u_row + gl_GlobalInvocationID.x; }

vec3 layer_at(uint k, uint i) {
  uint o = k * u_stride + 3u * i;
  return vec3(layer_skins[o], layer_skins[o + 1u], layer_skins[o + 2u]);
}

float mask_at(uint k, uint i) { return mask_start[k] == kNoMask ? 1.0 : masks[mask_start[k] + i]; }

bool displacement(uint k) { return mask_start[u_layers + k] != 0u; }

void main() {
  uint i = invocation();
  if (i >= u_count) return;
  vec3 p = vec3(rest_skin[3u * i], rest_skin[3u * i + 1u], rest_skin[3u * i + 2u]);
  vec3 s = vec3(skin[3u * i], skin[3u * i + 1u], skin[3u * i + 2u]);
  if (u_mode == kBlend) {
    // Wires (Singh & Fiume), as combine_displacements kWeighted: the displacements d_0 = f_0 - p and
    // d_k = m_k (f_k - p) weighted by |d|^m relative to the largest (no overflow or underflow for any m)
    float largest = length(s - p);
    for (uint k = 0u; k < u_layers; ++k)
      if (!displacement(k)) largest = max(largest, length(mask_at(k, i) * (layer_at(k, i) - p)));
    vec3 sum = vec3(0.0);
    if (largest > 0.0) {
      vec3 d = s - p;
      float w = u_exponent == 0.0 ? 1.0 : pow(length(d) / largest, u_exponent);
      float wsum = w;
      sum = w * d;
      for (uint k = 0u; k < u_layers; ++k) {
        if (displacement(k)) continue;
        d = mask_at(k, i) * (layer_at(k, i) - p);
        w = u_exponent == 0.0 ? 1.0 : pow(length(d) / largest, u_exponent);
        sum += w * d;
        wsum += w;
      }
      sum /= wsum;  // >= 1: the largest weighs 1
    }
    s = p + sum;
    for (uint k = 0u; k < u_layers; ++k)  // the drivers' displacements, added to the blended skin
      if (displacement(k)) s += mask_at(k, i) * layer_at(k, i);
  } else {
    // in order: each layer takes over where its mask is 1; sum: the masked displacements added to f_0
    // a driver's displacement is added where it sits
    for (uint k = 0u; k < u_layers; ++k) {
      vec3 f = layer_at(k, i);
      if (displacement(k)) s += mask_at(k, i) * f;
      else s += u_mode == kInOrder ? mask_at(k, i) * (f - s) : mask_at(k, i) * (f - p);
    }
  }
  skin[3u * i] = s.x;
  skin[3u * i + 1u] = s.y;
  skin[3u * i + 2u] = s.z;
}
