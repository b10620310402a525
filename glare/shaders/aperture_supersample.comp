#version 450
// Draws the eye's aperture (glare/eye/aperture_geometry.h) at one sample per texel of the supersampled
// grid: the pupil disc, then the product of the transmittances of every disc, line and polygon whose
// region contains the sample point (Ritschel et al. 2009, section 4: parts attenuate in series).
// Coverage rule, shared with the CPU rasteriser: a sample belongs to a primitive when its point is
// inside it - disc: distance <= radius; line: distance to the segment <= width / 2; polygon: even-odd.
// Texel (a, b): a to the right, b down from the top row; its point in millimetres is
//   x = (a + 0.5 - c) h, y = (c - b - 0.5) h, with S = N s samples across, h = width / S and
//   c = (S + s) / 2 the axis in sample units: the centre of pixel (N/2, N/2), as glare/eye/aperture_raster.h
//   states (sub-sample a' of pixel i at x = (i - N/2 - 1/2 + (a' + 1/2) / s) dx).
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32f, binding = 0) uniform writeonly image2D uSamples;

struct Disc { vec4 centre_radius_transmittance; };
struct Line { vec4 ends; vec4 half_width_transmittance; };
struct Polygon { uint first_vertex; uint vertex_count; float transmittance; float unused; };
layout(std430, binding = 0) readonly buffer Discs { Disc discs[]; };
layout(std430, binding = 1) readonly buffer Lines { Line lines[]; };
layout(std430, binding = 2) readonly buffer Polygons { Polygon polygons[]; };
layout(std430, binding = 3) readonly buffer Vertices { vec2 vertices[]; };
layout(std430, binding = 4) readonly buffer BinOffsets { uint bin_offsets[]; };  // B * B + 1, row-major, bin row 0 at the top
layout(std430, binding = 5) readonly buffer BinItems { uint bin_items[]; };      // disc index, or line index | 0x80000000

uniform int uSamplesAcross;  // S = N * supersampling
uniform float uSampleMm;     // h
uniform float uAxisSamples;  // c = (S + s) / 2
uniform float uPupilRadiusMm;
uniform int uBinsAcross;  // B: the grid is split into B x B bins of S / B samples (S a multiple of B)
uniform int uPolygonCount;

float squared_distance_to_segment(vec2 p, vec2 a, vec2 b) {
  const vec2 ab = b - a;
  const float length_squared = dot(ab, ab);
  const float t = length_squared > 0.0 ? clamp(dot(p - a, ab) / length_squared, 0.0, 1.0) : 0.0;
  const vec2 d = p - (a + t * ab);
  return dot(d, d);
}

bool inside_polygon_even_odd(vec2 p, uint first, uint count) {
  bool inside = false;
  for (uint i = 0u, j = count - 1u; i < count; j = i++) {
    const vec2 vi = vertices[first + i];
    const vec2 vj = vertices[first + j];
    if ((vi.y > p.y) != (vj.y > p.y) && p.x < (vj.x - vi.x) * (p.y - vi.y) / (vj.y - vi.y) + vi.x) inside = !inside;
  }
  return inside;
}

// Culling without barriers: the CPU sorts discs and lines into a grid of square bins by their
// bounding boxes grown by one sample (conservative, so coverage is unchanged). A bin's list holds
// the discs, then the lines, each in index order, so the product of transmittances is formed in
// the same order for every sample (deterministic) and only nearby primitives are tested.
void main() {
  const ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (texel.x >= uSamplesAcross || texel.y >= uSamplesAcross) return;
  const vec2 p = vec2(float(texel.x) + 0.5 - uAxisSamples, uAxisSamples - float(texel.y) - 0.5) * uSampleMm;
  float transmittance = dot(p, p) <= uPupilRadiusMm * uPupilRadiusMm ? 1.0 : 0.0;
  if (transmittance == 0.0) {
    imageStore(uSamples, texel, vec4(0.0));
    return;
  }
  // Bin of this sample: texels are binned by integer arithmetic, so no rounding decides the bin.
  const ivec2 bin = min(texel * uBinsAcross / uSamplesAcross, ivec2(uBinsAcross - 1));
  const int bin_index = bin.y * uBinsAcross + bin.x;
  const uint first = bin_offsets[bin_index], last = bin_offsets[bin_index + 1];
  for (uint item = first; item < last && transmittance > 0.0; ++item) {
    const uint code = bin_items[item];
    if ((code & 0x80000000u) == 0u) {
      const vec4 disc = discs[code].centre_radius_transmittance;
      const vec2 d = p - disc.xy;
      if (dot(d, d) <= disc.z * disc.z) transmittance *= disc.w;
    } else {
      const uint i = code & 0x7fffffffu;
      const vec2 hw = lines[i].half_width_transmittance.xy;
      if (squared_distance_to_segment(p, lines[i].ends.xy, lines[i].ends.zw) <= hw.x * hw.x) transmittance *= hw.y;
    }
  }
  // Polygons (eyelids) are few and large: not binned.
  for (int i = 0; i < uPolygonCount && transmittance > 0.0; ++i)
    if (polygons[i].vertex_count >= 3u && inside_polygon_even_odd(p, polygons[i].first_vertex, polygons[i].vertex_count))
      transmittance *= polygons[i].transmittance;
  imageStore(uSamples, texel, vec4(transmittance));
}
