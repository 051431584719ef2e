#pragma once
// The row loops of the warps and the blend (Warp.h's projections of a row, the 1D depth warp's
// positions, the sub-pixel grid and the row tables of Interpolation.h, the two-view blend), compiled
// for each x86-64 level the binary has (Rows.cpp, once per level) and chosen at start by the CPU
// (x86Level(), Common/CpuLevel.h), as the rasteriser is (QuadRow.h). Plain functions on plain
// pointers and plain structs (no member functions, so nothing of one level's code is shared with
// another's). Every level writes the same bits: the same operations in the same order, no
// contraction into fused multiply-adds (-ffp-contract=off), IEEE rounding in every lane.
#include <cstddef>
#include <cstdint>

namespace vs {

// The inverse depth of a hole, kNoDepth (Synth/Layer.h, which the kernels do not include; the callers
// check that the two are equal).
constexpr double kKernelNoDepth = -1.0;

// The general projection of ViewProjection (Synth/Warp.h) as numbers: p = a (M (u, v, 1)) + o w.
struct ProjectionCoefficients {
  double m[3][3];
  double o[3];
};

// What the two-view blend reads and writes (Synth/Blend.cpp's blendTwoViews: the decisions of its
// general blend for two views, with the weights' consequences computed once).
struct TwoViewBlendRows {
  const double* depth0;
  const double* depth1;
  const uint8_t* edge0;
  const uint8_t* edge1;
  const float* colour0[3];
  const float* colour1[3];
  double weight0, weight1, tolerance;
  float floatWeight0, floatWeight1;
  bool dominantFirst, dominantSecond;                       // weight >= 1: copied where it is valid
  bool pickSecondOfBoth, pickSecondAlone, pickFirstAlone;   // the general blend's bestView, from the weights
  bool plain;  // no dominant view and both weights pickable: the short form of the decisions applies
  float* colourOut[3];
  double* depthOut;
  uint8_t* holeOut;
};

// One row of the general texture warp (Synth/TextureWarp.cpp) for the look-ups that read the row's own
// table (Interpolation.h's SampledRow): its samples' reference positions (backwardRow), the tables of
// its channels as numbers, and the row's outputs. The chroma warp's (chromaTableRow) gives the grid
// indices too; the texture warp's (textureTableRow) are computed in the kernel, as textureLookups
// gives them.
struct TextureTableRow {
  const double* u;
  const double* v;
  const uint8_t* ok;
  const double* gridU;               // chroma: the grid indices of u and v (texture: not read)
  const double* gridV;
  const double* nearest;             // not read
  double precision;                  // texture: the sampler's grid positions per sample
  double rowGrid;                    // the grid index of the row's own reference row
  double lastU, lastV;               // the reference's width - 0.5 and height - 0.5
  const float* table[3];             // per channel: phase p, integer part ix at table[p * stride + ix - first]
  long long first, last;             // the integer parts the tables hold
  long long stride;
  int shift;                         // the grid index's integer part: index >> shift, phase: index & mask
  long long mask;
  int channels;
  const uint8_t* edges;              // the reference's edge flags, read at nearest
  double* depth;                     // the row's inverse depths, colours and edge flags
  float* colour[3];
  uint8_t* edgeOut;
};

// One row of the 1D texture warp (Synth/RowPath.cpp): its samples' reference positions along the
// reference row (ViewProjection::rowSources), the row tables of its channels (Interpolation.h's
// SampledRow, as numbers) and the row's outputs.
struct RowTableRow {
  const double* u;
  double precision;                  // the sampler's grid positions per sample
  double lastU;                      // the reference's width - 0.5
  double lastColumn;                 // the reference's width - 1
  const float* table[3];             // per channel: phase p, integer part ix at table[p * stride + ix - first]
  long long first, last;             // the integer parts the tables hold
  long long stride;
  int shift;                         // the grid index's integer part: index >> shift, phase: index & mask
  long long mask;
  int channels;
  const uint8_t* edges;              // the reference row's edge flags, read at the nearest sample (chroma:
                                     // the row's own, read at x)
  double* depth;                     // the row's inverse depths, colours and edge flags
  float* colour[3];
  uint8_t* edgeOut;
};

struct RowKernels {
  // ViewProjection::forwardRow's general loop (DepthType 0, not parallel): positions x, y of the
  // reference samples (u, v), u in [0, n), and their inverse target depths wv (-1 where it fails).
  void (*forwardRow)(const ProjectionCoefficients& forward, const double* inverseDepth, int n, double v, double* x,
                     double* y, double* wv);
  // ViewProjection::backwardRow's general loop: target samples (i * step + start, y) with inverse
  // depth wv[i] -> reference positions u[i], v[i] and ok[i].
  void (*backwardRow)(const ProjectionCoefficients& backward, const double* wv, int n, double y, double* u,
                      double* v, uint8_t* ok, int step, double start);
  // ViewProjection::rowSources: u[i] = snap((i * step + start - offset - shift wv[i]) * inverse), or
  // divided by scale where inverse is 0.
  void (*rowSources)(double offset, double shift, double inverse, double scale, const double* wv, int n, double* u,
                     int step, double start);
  // The 1D depth warp's positions (Synth/RowWarp.cpp): for x in [0, width), level = table[min(levels[x],
  // beyond)] (pairs of displacement, depth), xs[x] = snap(scale x + offset + displacement), ws[x] =
  // depth where xs[x] is finite, else -1.
  void (*rowTargets)(const uint16_t* levels, int width, const double* table, size_t beyond, double scale,
                     double offset, double* xs, double* ws);
  // The 1D depth warp's points (Synth/RowWarp.cpp): each sample x with ws[x] >= 0 raises z at its
  // nearest pixel centre floor(xs[x] + 0.5) when that lies in [0, outWidth) (the larger inverse depth,
  // compared as signed 64-bit integers, as Synth/Raster.h's raiseCell does).
  void (*rowPoints)(const double* xs, const double* ws, int width, double* z, int outWidth);
  // Its segments between neighbours x, x + 1 on one surface (both ws >= 0, at most discontinuity
  // apart; with splatting 2 only where nearBoundary flags one of them, with 0 none), rasterised at the
  // pixel centres they cover (z raised as rowPoints does, with the depth interpolated along the
  // segment), but for those that add nothing to the points. segments: width ints of working space.
  void (*rowSegments)(const double* xs, const double* ws, int width, const uint8_t* nearBoundary, int splatting,
                      double discontinuity, double* z, int outWidth, int* segments);
  // The general texture warp's look-ups (Synth/TextureWarp.cpp) of reference positions (u[i], v[i]):
  // their grid indices gridU[i] = floor(u[i] * precision + 0.5) (Interpolation.h's
  // SampledRow::gridIndex) and gridV[i] likewise, and the index of their nearest
  // reference sample, (clamp(floor(v + 0.5), 0, height - 1) * width + clamp(floor(u + 0.5), 0,
  // width - 1), as a double (exact); 0 for a position that is not a number.
  void (*textureLookups)(const double* u, const double* v, int n, double precision, int width, int height,
                         double* gridU, double* gridV, double* nearest);
  // The general texture warp's row (TextureTableRow) from sample `from` on, for samples with depth not
  // below 0 (NaN included): one whose look-up fails (!ok, or u, v outside [-0.5, lastU], [-0.5, lastV])
  // gets depth kKernelNoDepth; one on the row's own reference row (gridV == rowGrid) whose grid index
  // lies in the tables (|gridU| < 2^52, first <= gridU >> shift <= last) gets colour[c] from table c
  // and edgeOut = edges[nearest] (gridU, gridV and nearest as textureLookups gives them, with the
  // picture's size lastU + 0.5 by lastV + 0.5); every other one is appended to rest (rest[count++] = x), for the
  // caller's general look-up. With tablesReady false the tables are not read: the kernel returns the
  // first x (a multiple of its lanes past `from`) of a run of samples one of which would read them,
  // nothing from there on done; otherwise, and when every sample is done, width.
  int (*textureTableRow)(const TextureTableRow& row, int from, int width, bool tablesReady, int* rest, int& count);
  // The 1D texture warp's look-ups (Synth/RowPath.cpp) of reference positions u[i] along a row: their
  // grid indices gridU[i], as textureLookups gives, and their nearest reference sample clamp(floor(u +
  // 0.5), 0, width - 1), as a double; 0 for a position that is not a number.
  void (*rowLookups)(const double* u, int n, double precision, int width, double* gridU, double* nearest);
  // The chroma look-up positions on the 1D path (Synth/ChromaWarp.cpp): x[i] = (x[i] - offset) / block,
  // then its grid index g[i] = floor(x[i] * precision + 0.5).
  void (*chromaGridIndices)(double* x, int n, double offset, double block, double precision, double* g);
  // A row table's interior for one phase (Interpolation.h's SampledRow::build): out[n] = the sum over
  // the TAPS kernel weights k[t] * taps[n + t], in that order, from 0, for n in [0, count); TAPS 2, 4, 6.
  // Phase 0 of a row table: out[n] = taps[n] (every kernel is (0, .., 1, .., 0) there).
  void (*sampleRowPhase0)(const uint16_t* taps, long long count, float* out);
  void (*sampleRowPhase2)(const uint16_t* taps, const float* k, long long count, float* out);
  void (*sampleRowPhase4)(const uint16_t* taps, const float* k, long long count, float* out);
  void (*sampleRowPhase6)(const uint16_t* taps, const float* k, long long count, float* out);
  // The same sums from taps already converted to floats (a row table's phase 0: float(sample) exactly),
  // out[n] = the sum over k[t] * taps[n + t], in that order, from 0; taps and out do not overlap.
  void (*sampleFloatRowPhase2)(const float* taps, const float* k, long long count, float* out);
  void (*sampleFloatRowPhase4)(const float* taps, const float* k, long long count, float* out);
  void (*sampleFloatRowPhase6)(const float* taps, const float* k, long long count, float* out);
  // MergingOption 2's hole counting (Synth/RowPath.cpp's flagCrowdedHoles). holeCounts: count[x] = the
  // holes (depth < 0) among depth[x - 3 .. x + 3] of a row of width samples, none beyond its ends;
  // padded: width + 6 bytes of working space whose first and last three are 0. windowStep: sum[x] +=
  // entering[x], then sum[x] -= leaving[x] (byte arithmetic; either may be null: skipped), then, unless
  // edge is null, edge[x] |= sum[x] > most.
  void (*holeCounts)(const double* depth, int width, uint8_t* padded, uint8_t* count);
  void (*windowStep)(uint8_t* sum, const uint8_t* entering, const uint8_t* leaving, uint8_t* edge, int width, int most);
  // The reference depth steps of a row (Synth/ReferenceEdges.cpp): step[x] = 1 where level row[x] is
  // `missing`, or a neighbour (row[x - 1], row[x + 1], above[x], below[x]; the sample itself beyond
  // the row's ends) is `missing` or differs from it by minStep levels or more; else 0. `missing` -1:
  // no level is missing.
  void (*referenceSteps)(const uint16_t* row, const uint16_t* above, const uint16_t* below, int width, int missing,
                         int minStep, uint8_t* step);
  // Depth edge alignment's edges (Synth/EdgeAlign.cpp): flags[x] = 1 where levels a[x] and b[x] are
  // neither `missing` (-1: none is) and differ by minStep or more; else 0, for x in [0, n).
  void (*depthEdgePairs)(const uint16_t* a, const uint16_t* b, int n, int missing, int minStep, uint8_t* flags);
  // Crack closing's candidates (Synth/Cracks.cpp): flags[i] = 1 where behind[i] < front[i] - limit (a
  // sample more than the tolerance behind its neighbour; NaN compares false), else 0, for i in [0, n).
  void (*behindFlags)(const double* front, const double* behind, int n, double limit, uint8_t* flags);
  // The two-view blend of samples [begin, end), for 1, 2 or 3 channels, each with and without
  // NearestViewOnly ([channels - 1][nearestViewOnly]); true where the general blend finds no bestView.
  bool (*blendTwoViews[3][2])(const TwoViewBlendRows& blend, size_t begin, size_t end);
  // The chroma warp's whole 2x2 blocks (Synth/ChromaWarp.cpp, 4:2:0): block i covers luma samples 2i
  // and 2i + 1 of rows top and bottom (inverse depths and edge flags), in the order top 2i, top 2i + 1,
  // bottom 2i, bottom 2i + 1. front = the largest of kKernelNoDepth and the four (front = front < d ? d
  // : front, in that order); a sample is on the front where d >= 0 and front - d <= surface. depth[i] =
  // kKernelNoDepth where front < 0, else the sum of the front's depths (from +0.0, in that order)
  // divided by their count; edge[i] = the OR of their edge flags. For i in [0, n).
  void (*chromaBlocks)(const double* top, const double* bottom, const uint8_t* edgeTop, const uint8_t* edgeBottom,
                       int n, double surface, double* depth, uint8_t* edge);
  // The chroma warp's general look-ups (Synth/ChromaWarp.cpp): textureTableRow's rule but for the
  // look-up's bounds, [-1, lastU] and [-1, lastV] (lastU, lastV: the reference chroma's width and
  // height), the grid indices, read from gridU and gridV, and the edge flag of a table's sample,
  // edgeOut[x] = edges[x].
  int (*chromaTableRow)(const TextureTableRow& row, int from, int width, bool tablesReady, int* rest, int& count);
  // CleanNoiseOption's isolated samples of a row (Synth/RowPath.cpp): isolated[x] = 1 where row[x] >= 0,
  // row[x - 1] < 0 and row[x + 1] < 0, else 0, for x in [1, width - 1) (the first and last flags are
  // not written).
  void (*isolatedSamples)(const double* row, int width, uint8_t* isolated);
  // The occlusion rule's column scans of two views (Synth/Occlusion.cpp's rejectBetweenTwoViews), one
  // row of n columns. occlusionDown finds the row's candidates and keeps the columns' last valid
  // samples: sole[x] = first where row0[x] >= 0 and row1[x] is not, second where row1[x] >= 0 and
  // row0[x] is not, else none (first is 0 or none, second 1 or none, none above 1: a candidate is a
  // sole[x] of 0 or 1); the other view's last valid sample above each candidate, up[count++] =
  // sole[x] == 1 ? last0[x] : last1[x], in the order of x (packed: the candidates are few); then
  // lastK[x] = rowK[x] >= 0 ? rowK[x] : lastK[x] (K = 0, 1). Returns count. up[count, n) may be
  // written over too. occlusionUp decides the candidates on the way up: with belowK
  // and valueK the lastK[x] and rowK[x] it finds, lastK[x] = valueK >= 0 ? valueK : belowK; where
  // sole[x] = k is 0 or 1 (a candidate of view k), with below the other view's belowK, own = valuek
  // and above the next of the row's packed samples above (in the order of x): around =
  // around[x], then std::min(around, std::min(below, above)) where below >= 0 and above >= 0; the
  // candidate's rowk[x] = kKernelNoDepth where around != HUGE_VAL and own < around - steps. (around is
  // read at the candidates only.) The row's packed samples are the last before upEnd: they are taken
  // from there backwards, and their count is returned. aboveRow: n doubles of working space, read
  // whatever it holds (initialised memory).
  int (*occlusionDown)(const double* row0, const double* row1, uint8_t first, uint8_t second, uint8_t none,
                       uint8_t* sole, double* last0, double* last1, double* up, int n);
  int (*occlusionUp)(const uint8_t* sole, double* row0, double* row1, double* last0, double* last1, const double* upEnd,
                     const double* around, double steps, int n, double* aboveRow);
  // The 1D texture warp's row (RowTableRow), for samples with depth not below 0 (NaN included): one
  // whose position u fails (not in [-0.5, lastU]: NaN and the infinities fail) gets depth
  // kKernelNoDepth; any other gets edgeOut = edges[clamp(floor(u + 0.5), 0, lastColumn)] and, where
  // its grid index g = floor(u * precision + 0.5) (SampledRow::gridIndex) has its integer part
  // g >> shift in [first, last], colour[c] from table c at (g & mask) * stride + (g >> shift) - first;
  // where not, it is appended to rest (rest[count++] = x), for the caller's look-up of its colour.
  void (*rowTableRow)(const RowTableRow& row, int width, int* rest, int& count);
  // The 1D chroma warp's row (Synth/ChromaWarp.cpp): rowTableRow's rule but for the low bound, -1 (lastU:
  // the chroma width), and the edge flag, edgeOut[x] = edges[x] (the block's; lastColumn is not read).
  void (*chromaRowTableRow)(const RowTableRow& row, int width, int* rest, int& count);
  int level;  // the x86-64 level they are compiled for (0: not x86-64)
};

// The kernels for x86Level().
const RowKernels& rowKernels();
// The kernels compiled for `level`; nullptr when this binary has none for it (tests compare levels).
const RowKernels* rowKernelsFor(int level);

}  // namespace vs
