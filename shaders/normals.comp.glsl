#version 430 core
// Smooth vertex normals of the deformed skin on the GPU (render/gpu_deformer.h), as
// core/mesh_normals.cpp computes them: each triangle's cross product (length = twice its area),
// then per vertex the sum over its triangles in the order of a vertex -> triangles table uploaded
// once (no atomics), normalized (zero where no triangle touches the vertex). Built twice, with
// KERNEL_FACES (one invocation per triangle) or KERNEL_VERTICES (one per vertex).
layout(local_size_x = 256) in;

uniform uint u_count;  // triangles or vertices
uniform uint u_row;    // invocations per row of the dispatch grid

uint invocation() { return gl_GlobalInvocationID.y * u_row + gl_GlobalInvocationID.x; }

layout(std430, binding = 2) buffer FaceNormals { float face_normals[]; };  // #T x 3

#if defined(KERNEL_FACES)
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };  // #V x 3, the drawn buffer
layout(std430, binding = 1) readonly buffer Triangles { uint triangles[]; };   // #T x 3, the index buffer
uniform uint u_vertices;

vec3 position(uint v) { return vec3(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u]); }

void main() {
  uint f = invocation();
  if (f >= u_count) return;
  uint a = triangles[3u * f], b = triangles[3u * f + 1u], c = triangles[3u * f + 2u];
  vec3 n = vec3(0.0);
  if (a < u_vertices && b < u_vertices && c < u_vertices) {
    vec3 p0 = position(a);
    n = cross(position(b) - p0, position(c) - p0);
  }
  face_normals[3u * f] = n.x;
  face_normals[3u * f + 1u] = n.y;
  face_normals[3u * f + 2u] = n.z;
}
#endif

#if defined(KERNEL_VERTICES)
layout(std430, binding = 0) writeonly buffer Normals { float normals[]; };  // #V x 3, the drawn buffer
layout(std430, binding = 1) readonly buffer Starts { uint starts[]; };     // #V + 1
layout(std430, binding = 3) readonly buffer Incident { uint incident[]; };  // triangles around each vertex

void main() {
  uint v = invocation();
  if (v >= u_count) return;
  vec3 n = vec3(0.0);
  uint end = starts[v + 1u];
  for (uint k = starts[v]; k < end; ++k) {
    uint f = incident[k];
    n += vec3(face_normals[3u * f], face_normals[3u * f + 1u], face_normals[3u * f + 2u]);
  }
  float len = length(n);
  n = len > 0.0 ? n / len : vec3(0.0);
  normals[3u * v] = n.x;
  normals[3u * v + 1u] = n.y;
  normals[3u * v + 2u] = n.z;
}
#endif
