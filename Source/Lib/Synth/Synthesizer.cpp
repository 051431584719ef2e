#include "Synth/Synthesizer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "Common/Depth.h"
#include "Common/Error.h"
#include "Synth/Colour.h"
#include "Synth/Cracks.h"
#include "Synth/Flags.h"
#include "Synth/Occlusion.h"
#include "Synth/Plan.h"
#include "Synth/Raster.h"
#include "Synth/RowWarp.h"

namespace vs {

namespace {

// A depth step of this many 8-bit levels (scaled to the map's bit depth) separates two surfaces.
// A sample seen by one view only is dropped when it lies this many discontinuity steps behind every
// surface the other view shows around that spot (rejectOccludedInOtherViews).
constexpr double kBehindHoleSteps = 3.0;

// What WarpedLayer::reset leaves in rows [y0, y1): no depth, colour 0, no edge. The warps size their
// layers with resize() and clear each row in their parallel loops, where the row is about to be
// written anyway, instead of in one pass on one thread over the whole layer before.
void clearRows(WarpedLayer& layer, int y0, int y1) {
  const size_t begin = size_t(y0) * size_t(layer.width), end = size_t(y1) * size_t(layer.width);
  std::fill(layer.inverseDepth.data() + begin, layer.inverseDepth.data() + end, kNoDepth);
  for (int k = 0; k < layer.channels; ++k) std::fill(layer.colour[k].data() + begin, layer.colour[k].data() + end, 0.0f);
  std::fill(layer.edge.data() + begin, layer.edge.data() + end, uint8_t(0));
}

// CleanNoiseOption on one row of a layer's depth: a sample with holes on both sides along its row is
// a stray point of a surface seen elsewhere, removed before it picks up colour. Removing a sample
// never changes the decision for the next one (it is removed only when the next is a hole, which is
// then not removed either), so the decisions are taken on the row as it was: a branch-free pass that
// vectorises flags the samples (in `isolated`, width bytes), and only those are then cleared.
void cleanIsolatedSamples(double* row, int width, uint8_t* isolated) {
  if (width < 3) return;
  for (int x = 1; x + 1 < width; ++x) isolated[x] = uint8_t((row[x] >= 0) & (row[x - 1] < 0) & (row[x + 1] < 0));
  forEachFlag(isolated + 1, width - 2, [&](int x) { row[x + 1] = kNoDepth; });
}

}  // namespace

Synthesizer::Synthesizer(const Scene& scene, SynthesisMode mode)
    : scene_(scene),
      parallel_(mode == SynthesisMode::Parallel1D),
      outputFormat_(scene.settings.textureFormat),
      rgb_(scene.settings.colorSpace == 1),
      hasChroma_(scene.settings.textureFormat.chroma != ChromaFormat::Yuv400),
      sampler_(scene.settings.precision, scene.settings.filter),
      aligner_(scene.settings) {
  const SynthesisSettings& s = scene.settings;
  double inverseRange = 0;
  std::vector<double> distances, angles;
  for (const ReferenceView& reference : s.references) {
    ViewState view(ViewProjection(reference.camera, scene.virtualCamera, s.depthType, parallel_));
    view.levelToInverseDepth = inverseZTable(reference.depthRange);
    if (s.missingDepthLevel >= 0) view.levelToInverseDepth[size_t(s.missingDepthLevel)] = std::nan("");
    if (parallel_) {
      // The 1D warp's inverse camera depth per level, NaN where forward() refuses the level (missing,
      // behind, infinite): on a rectified pair it does not depend on the pixel.
      view.levelToRowDepth.resize(view.levelToInverseDepth.size());
      for (size_t level = 0; level < view.levelToRowDepth.size(); ++level) {
        double x, y, wv;
        const double inverseDepth = view.levelToInverseDepth[level];
        view.levelToRowDepth[level] =
            !std::isnan(inverseDepth) && view.projection.forward(0.0, 0.0, inverseDepth, x, y, wv) ? wv : std::nan("");
      }
    }
    const double farInverse = std::isinf(reference.depthRange.zfar) ? 0.0 : 1.0 / reference.depthRange.zfar;
    inverseRange += std::fabs(1.0 / reference.depthRange.znear - farInverse);
    distances.push_back(norm(reference.camera.centre() - scene.virtualCamera.centre()));
    // Angle between the optical axes (rows 2 of R are the viewing directions in world coordinates).
    const double cosine = dot(reference.camera.R.row(2), scene.virtualCamera.R.row(2)) /
                          (norm(reference.camera.R.row(2)) * norm(scene.virtualCamera.R.row(2)));
    angles.push_back(std::acos(std::clamp(cosine, -1.0, 1.0)));
    views_.push_back(std::move(view));
  }
  inverseRange /= double(s.references.size());
  // Thresholds sit half a level past the whole number of 8-bit levels they name: inverse depths of
  // quantised maps differ by whole levels, so a difference never ties with a threshold and a change of
  // units or of world origin cannot flip a decision through rounding.
  auto levels = [&](double levels8) { return (levels8 + 0.5) / 255.0 * inverseRange; };
  discontinuity_ = levels(kSurfaceStepLevels8);
  edgeLevelStep_ = depthEdgeStep(s.depthFormat.maxValue());
  // A view's distance from the virtual camera counts its position and its viewing direction: the
  // angle between optical axes (radians) is scaled by the mean camera distance, so a parallel rig
  // keeps VSRS's baseline weights.
  double meanDistance = 0;
  for (double d : distances) meanDistance += d / double(distances.size());
  for (size_t k = 0; k < distances.size(); ++k) {
    // A view whose parallax against the virtual camera stays below 1e-3 px everywhere (baseline
    // times the nearest inverse depth, plus the turn between the optical axes, in pixels) is the
    // virtual camera for every purpose: it decides alone where it is valid.
    const ReferenceView& reference = s.references[k];
    const double nearest = std::max(std::fabs(1.0 / reference.depthRange.znear),
                                    std::isinf(reference.depthRange.zfar) ? 0.0 : std::fabs(1.0 / reference.depthRange.zfar));
    const double parallax = scene.virtualCamera.K[0][0] * (distances[k] * nearest + angles[k]);
    if (parallax < 1e-3) distances[k] = 0;
    else distances[k] += meanDistance * angles[k];
  }
  blendOptions_.weights = baselineWeights(distances);
  blendOptions_.depthTolerance = levels(s.depthBlendDifference);
  if (parallel_) {
    // VSRS's 1D MergingOption: 0 z-buffer only (one level of tolerance), 1 averaging only,
    // 2 adaptive: mixed within DepthThreshold levels (by default DepthBlendDifference's, so that the
    // 1D path blends as the general one does), hole counting decides between views.
    if (s.oneD.merging == 0) blendOptions_.depthTolerance = levels(1);
    else if (s.oneD.merging == 1) blendOptions_.depthTolerance = HUGE_VAL;
    else if (s.oneD.depthThreshold >= 0) blendOptions_.depthTolerance = levels(s.oneD.depthThreshold);
  }
  blendOptions_.nearestViewOnly = s.viewBlending == 1;
  fillOptions_.backgroundFirst = s.ivsrsInpaint;
  // Row runs follow the disocclusions of a rectified rig, which lie along rows. On any other rig they
  // do not (open3d: 33.29 dB with them), and hole filling stays the directional and inpainting
  // estimates mixed 1 : 1 (33.96 dB), the mix the weights of the three were chosen against.
  if (!rectifiedRig(scene)) {
    fillOptions_.directionalWeight = fillOptions_.inpaintWeight = 1.0f;
    fillOptions_.rowRunWeight = 0.0f;
  }
  fillOptions_.depthTolerance = levels(s.depthBlendDifference);
  const float mid = float(1 << (outputFormat_.bitDepth - 1));
  fillOptions_.emptyValue[0] = rgb_ ? mid : float(16 << (outputFormat_.bitDepth - 8));
  fillOptions_.emptyValue[1] = fillOptions_.emptyValue[2] = mid;
  if (rgb_) fillOptions_.emptyValue[0] = fillOptions_.emptyValue[1] = fillOptions_.emptyValue[2] = mid;
}

void Synthesizer::markReferenceEdges(ViewState& view, const Plane& depth) {
  const int w = depth.width, h = depth.height;
  std::vector<uint8_t>& step = view.referenceStep;
  step.resize(size_t(w) * h);
  const int missing = scene_.settings.missingDepthLevel, minStep = edgeLevelStep_;
  // A sample is a step when it is missing, or a neighbour (left, right, above, below) is missing or
  // differs by minStep levels or more. A neighbour beyond the border is read as the sample itself,
  // which adds nothing (a sample differs from itself only by being missing). Bitwise operators keep
  // the loop free of branches, so that it vectorises.
  // (Locals, not the captured variables, inside the loops: a byte store could alias those, which
  // keeps the compiler from vectorising.)
  parallelRanges(h, [&](int y0, int y1) {
    const int width = w, height = h, miss = missing, least = minStep;
    for (int y = y0; y < y1; ++y) {
      const uint16_t* row = depth.row(y);
      const uint16_t* above = y > 0 ? depth.row(y - 1) : row;
      const uint16_t* below = y + 1 < height ? depth.row(y + 1) : row;
      uint8_t* out = step.data() + size_t(y) * width;
      auto at = [=](int x, int left, int right) {
        const int level = row[x];
        auto differs = [=](int other) { return (other == miss) | (std::abs(level - other) >= least); };
        return uint8_t((level == miss) | differs(row[left]) | differs(row[right]) | differs(above[x]) |
                       differs(below[x]));
      };
      out[0] = at(0, 0, std::min(1, width - 1));
      for (int x = 1; x + 1 < width; ++x) out[x] = at(x, x - 1, x + 1);
      if (width > 1) out[width - 1] = at(width - 1, width - 2, width - 1);
    }
  });
  // Dilated by one sample: the colours on both sides of an edge are mixed by the camera's optics.
  // (1D mode with WarpEnhancementOption 0 does without these reliability flags.)
  std::vector<uint8_t>& edge = view.referenceEdge;
  if (parallel_ && !scene_.settings.oneD.warpEnhancement) {
    edge.assign(size_t(w) * h, 0);
    return;
  }
  edge.resize(size_t(w) * h);  // every sample is written below
  // Separable: OR over three samples along rows, then along columns.
  std::vector<uint8_t>& rows = view.referenceStepRows;
  rows.resize(size_t(w) * h);
  parallelRanges(h, [&](int y0, int y1) {
    const int width = w;
    for (int y = y0; y < y1; ++y) {
      const uint8_t* in = step.data() + size_t(y) * width;
      uint8_t* out = rows.data() + size_t(y) * width;
      // Border samples read themselves for the missing neighbour; the rest run without branches.
      out[0] = in[0] | in[std::min(1, width - 1)];
      for (int x = 1; x + 1 < width; ++x) out[x] = in[x - 1] | in[x] | in[x + 1];
      if (width > 1) out[width - 1] = in[width - 2] | in[width - 1];
    }
  });
  parallelRanges(h, [&](int y0, int y1) {
    const int width = w, height = h;
    for (int y = y0; y < y1; ++y) {
      const uint8_t* mid = rows.data() + size_t(y) * width;
      const uint8_t* up = y > 0 ? mid - width : mid;
      const uint8_t* down = y + 1 < height ? mid + width : mid;
      uint8_t* out = edge.data() + size_t(y) * width;
      for (int x = 0; x < width; ++x) out[x] = mid[x] | up[x] | down[x];
    }
  });
}

void Synthesizer::warpDepth(ViewState& view, const Plane& depth) {
  if (parallel_) {
    warpDepthRows(view, depth);
    return;
  }
  const int w = depth.width, h = depth.height;
  const int outW = outputFormat_.width, outH = outputFormat_.height;
  view.luma.resize(outW, outH, rgb_ ? 3 : 1);  // cleared row by row (clearRows)
  // Where the views run side by side, or there is one thread (OpenCV then runs every loop on the
  // calling thread), this view's thread is the only writer: the triangles are drawn straight into the
  // layer's depth. Otherwise into an atomic z-buffer, then copied.
  const bool lone = viewsSideBySide() || cv::getNumThreads() <= 1;
  if (lone) parallelRanges(outH, [&](int y0, int y1) { clearRows(view.luma, y0, y1); });
  else view.zbuffer.reset(size_t(outW) * outH, kNoDepth);
  // Row by row: each reference row is projected into the virtual view (forwardRow), its samples are
  // raised as points, and the quads between it and the row above are rasterised while both rows are
  // at hand (two rows of positions, not the whole picture's). A range of rows also projects the row
  // after its last, for the quads between them; that row's points are raised by the range holding it.
  auto drawInto = [&](const auto& raise) {
    parallelRanges(h, [&](int y0, int y1) {
      // Locals: the stores below are doubles, which may alias the projection's and the table's.
      const ViewProjection projection = view.projection;
      const double* levelToInverseDepth = view.levelToInverseDepth.data();
      const int width = w, height = h, outWidth = outW, outHeight = outH;
      const double discontinuity = discontinuity_;
      const auto put = raise;  // a copy no store can change: what it holds stays in registers
      // A row's inverse depths first (a look-up per sample), then its projection in a loop that
      // vectorises. A level declared missing has a NaN inverse depth: not warped.
      static thread_local std::vector<double> inverseRow, rowBuffers;
      inverseRow.resize(size_t(width));
      rowBuffers.resize(size_t(width) * 6);
      double* inverse = inverseRow.data();
      // Positions and inverse depths of two rows: the one above (the quads' top) and the current.
      double *xAbove = rowBuffers.data(), *yAbove = xAbove + width, *wAbove = yAbove + width;
      double *xs = wAbove + width, *ys = xs + width, *ws = ys + width;
      auto project = [&](int y) {
        const uint16_t* levels = depth.row(y);
        for (int x = 0; x < width; ++x) inverse[x] = levelToInverseDepth[levels[x]];
        projection.forwardRow(inverse, width, y, xs, ys, ws);
      };
      for (int y = y0; y <= y1 && y < height; ++y) {
        project(y);
        // Every sample also lands as a point, so thin foreground keeps its width.
        if (y < y1) {
          for (int x = 0; x < width; ++x) {
            if (ws[x] < 0) continue;
            const double px = std::floor(xs[x] + 0.5), py = std::floor(ys[x] + 0.5);
            if (px < 0 || py < 0 || px >= outWidth || py >= outHeight) continue;
            put(size_t(py) * outWidth + size_t(px), ws[x]);
          }
        }
        if (y > y0)
          rasteriseQuadRow(put, width, outWidth, outHeight, discontinuity, xAbove, yAbove, wAbove, xs, ys, ws);
        std::swap(xAbove, xs);
        std::swap(yAbove, ys);
        std::swap(wAbove, ws);
      }
    });
  };
  if (lone) {
    drawInto(LoneRaise{view.luma.inverseDepth.data()});
  } else {
    AtomicMaxBuffer& zbuffer = view.zbuffer;
    drawInto([&zbuffer](size_t i, double value) { zbuffer.raise(i, value); });
    // The z-buffer becomes the layer's depth, and the rest of the layer is cleared, row by row.
    parallelRanges(outH, [&](int y0, int y1) {
      clearRows(view.luma, y0, y1);
      zbuffer.copyTo(size_t(y0) * outW, size_t(y1) * outW, view.luma.inverseDepth.data() + size_t(y0) * outW);
    });
  }
  closeCracks(view.luma.inverseDepth, outW, outH, discontinuity_);
}

void Synthesizer::warpDepthRows(ViewState& view, const Plane& depth) {
  // 1D: rows map to rows, so each thread warps whole rows straight into the layer (RowDepthWarp):
  // samples move along the row by the disparity of their level, the depth grid is rasterised as
  // segments between horizontal neighbours on one surface, and every sample also lands as a point.
  // SplattingOption 2 draws segments only within BoundaryGrowth samples of a reference depth edge.
  const int w = depth.width, h = depth.height;
  const int outW = outputFormat_.width, outH = outputFormat_.height;
  const OneDOptions& oneD = scene_.settings.oneD;
  view.luma.resize(outW, outH, rgb_ ? 3 : 1);  // cleared row by row below (clearRows)
  // Rows below the reference (an output taller than it) receive nothing.
  if (outH > h) clearRows(view.luma, h, outH);
  const RowDepthWarp rowWarp(view.projection, view.levelToRowDepth, discontinuity_, oneD.splatting);
  parallelRanges(std::min(h, outH), [&](int y0, int y1) {
    const int width = w, outWidth = outW, growth = oneD.boundaryGrowth;
    const bool nearEdges = oneD.splatting == 2;
    const bool cleanNoise = oneD.cleanNoise;
    // The row's boundary flags and isolated samples, kept per thread between frames.
    static thread_local std::vector<uint8_t> nearRow, isolatedRow;
    nearRow.resize(size_t(width));
    isolatedRow.resize(size_t(outWidth));
    for (int y = y0; y < y1; ++y) {
      clearRows(view.luma, y, y + 1);
      // Within BoundaryGrowth samples of a reference depth edge.
      if (nearEdges) markWithinReach(view.referenceStep.data() + size_t(y) * width, width, growth, nearRow.data());
      double* row = view.luma.inverseDepth.data() + size_t(y) * outWidth;
      rowWarp.warp(depth.row(y), width, nearRow.data(), row, outWidth);
      // A row is all its own warp writes: it is cleaned while it is at hand.
      if (cleanNoise) cleanIsolatedSamples(row, outWidth, isolatedRow.data());
    }
  });
  closeCracks(view.luma.inverseDepth, outW, outH, discontinuity_);
}

void Synthesizer::flagCrowdedHoles(ViewState& view) {
  WarpedLayer& layer = view.luma;
  // MergingOption 2's hole counting: a sample with more than HoleCountThreshold holes in its 7x7
  // neighbourhood is unreliable; where another view agrees and is not, that view is used.
  const int w = layer.width, h = layer.height, threshold = scene_.settings.oneD.holeCountThreshold;
  // Separable counts: holes among the 7 samples of each row around x (clipped at the borders), then
  // the sum of those over the 7 rows around y.
  std::vector<uint8_t>& rowHoles = view.rowHoleScratch;
  rowHoles.resize(size_t(w) * h);
  parallelRanges(h, [&](int y0, int y1) {
    // The row's hole flags with three clear flags on either side (beyond the border), then seven
    // shifted sums: both loops are branch-free byte loops that vectorise.
    static thread_local std::vector<uint8_t> paddedRow;
    paddedRow.assign(size_t(w) + 6, 0);
    uint8_t* padded = paddedRow.data();
    const int width = w;
    for (int y = y0; y < y1; ++y) {
      const double* depth = layer.inverseDepth.data() + size_t(y) * width;
      uint8_t* count = rowHoles.data() + size_t(y) * width;
      for (int x = 0; x < width; ++x) padded[x + 3] = uint8_t(depth[x] < 0);
      for (int x = 0; x < width; ++x)
        count[x] = uint8_t(padded[x] + padded[x + 1] + padded[x + 2] + padded[x + 3] + padded[x + 4] + padded[x + 5] +
                           padded[x + 6]);
    }
  });
  parallelRanges(h, [&](int rowBegin, int rowEnd) {
    const int width = w, height = h, most = threshold;  // locals: see markReferenceEdges
    // The 7 rows' sum (at most 49) as a window that slides down the thread's rows: the row entering
    // added, the one leaving taken away (byte arithmetic, exact as the sums stay below 256).
    static thread_local std::vector<uint8_t> sumRow;
    sumRow.assign(size_t(width), 0);
    uint8_t* sum = sumRow.data();
    auto add = [&](int r) {
      const uint8_t* count = rowHoles.data() + size_t(r) * width;
      for (int x = 0; x < width; ++x) sum[x] = uint8_t(sum[x] + count[x]);
    };
    auto remove = [&](int r) {
      const uint8_t* count = rowHoles.data() + size_t(r) * width;
      for (int x = 0; x < width; ++x) sum[x] = uint8_t(sum[x] - count[x]);
    };
    // Rows rowBegin - 4 to rowBegin + 2: the first step takes row rowBegin - 4 away again.
    for (int r = std::max(0, rowBegin - 4); r < std::min(height, rowBegin + 3); ++r) add(r);
    for (int y = rowBegin; y < rowEnd; ++y) {
      if (y + 3 < height) add(y + 3);
      if (y - 4 >= 0) remove(y - 4);
      uint8_t* edge = layer.edge.data() + size_t(y) * width;
      for (int x = 0; x < width; ++x) edge[x] |= uint8_t(sum[x] > most);
    }
  });
}

void Synthesizer::warpTexture(ViewState& view, const std::vector<const Plane*>& planes) {
  WarpedLayer& layer = view.luma;
  const int refW = planes[0]->width, refH = planes[0]->height;
  if (parallel_) {
    // Rows map to rows: the look-up stays in row y (as backward() gives v = y). The tap and channel
    // counts are compile-time constants, so that the channel loop unrolls.
    auto warpRows = [&](auto taps, auto channelCount) {
    constexpr int kTaps = decltype(taps)::value, kChannels = decltype(channelCount)::value;
    parallelRanges(std::min(layer.height, refH), [&](int y0, int y1) {
      // Local copies of what the loop reads: the edge flags are bytes, and a byte store may alias
      // anything the loop would otherwise read through a pointer or a capture, reloading it per sample.
      const ViewProjection projection = view.projection;
      const SubPixelSampler sampler = sampler_;
      const int width = layer.width, referenceWidth = refW;
      double* depth = layer.inverseDepth.data();
      float* colour[3] = {layer.colour[0].data(), layer.colour[1].data(), layer.colour[2].data()};
      uint8_t* edgeOut = layer.edge.data();
      // Each reference row sampled once at every grid position (SampledRow): the look-ups below are
      // loads. Positions in [-0.5, width - 0.5] have integer parts in [-1, width].
      static thread_local SampledRow sampledRows[3];
      // The row's source positions first, in a pass that vectorises (holes too: not read).
      static thread_local std::vector<double> sourceRow, gridRow;
      sourceRow.resize(size_t(width));
      gridRow.resize(size_t(width));
      double* sources = sourceRow.data();
      double* grid = gridRow.data();
      for (int y = y0; y < y1; ++y) {
        const uint8_t* edges = view.referenceEdge.data() + size_t(y) * referenceWidth;
        for (int c = 0; c < kChannels; ++c) sampledRows[c].build<kTaps>(sampler, *planes[size_t(c)], y, -1, referenceWidth);
        projection.rowSources(depth + size_t(y) * width, width, sources);
        for (int x = 0; x < width; ++x) grid[x] = sampledRows[0].gridIndex(sources[x]);
        for (int x = 0; x < width; ++x) {
          const size_t i = size_t(y) * width + x;
          if (depth[i] < 0) continue;
          const double u = sources[x];
          if (!std::isfinite(u) || u < -0.5 || u > referenceWidth - 0.5) {
            depth[i] = kNoDepth;
            continue;
          }
          for (int c = 0; c < kChannels; ++c) colour[c][i] = sampledRows[c].atGrid<kTaps>(u, grid[x]);
          edgeOut[i] = edges[std::clamp(int(std::floor(u + 0.5)), 0, referenceWidth - 1)];
        }
      }
    });
    };
    sampler_.withTaps([&](auto taps) {
      if (layer.channels == 3) warpRows(taps, std::integral_constant<int, 3>());
      else warpRows(taps, std::integral_constant<int, 1>());
    });
    // Rows below the reference (an output taller than it) look up nothing.
    for (size_t i = size_t(std::min(layer.height, refH)) * layer.width; i < layer.inverseDepth.size(); ++i)
      layer.inverseDepth[i] = kNoDepth;
    return;
  }
  sampler_.withTaps([&](auto taps) {
  constexpr int kTaps = decltype(taps)::value;
  parallelRanges(layer.height, [&](int y0, int y1) {
    // Locals, as in the 1D branch above.
    const ViewProjection projection = view.projection;
    const SubPixelSampler sampler = sampler_;
    const int width = layer.width, channels = layer.channels, referenceWidth = refW, referenceHeight = refH;
    double* depth = layer.inverseDepth.data();
    float* colour[3] = {layer.colour[0].data(), layer.colour[1].data(), layer.colour[2].data()};
    uint8_t* edgeOut = layer.edge.data();
    const uint8_t* edges = view.referenceEdge.data();
    // A look-up that lands on this row's own reference row (a whole row of the grid: every one on a
    // rectified rig) is the row sampler's value, read from the row's table (SampledRow, as on the 1D
    // path), built the first time one does; any other goes through the 2D kernel.
    static thread_local SampledRow sampledRows[3];
    int tableRow = -1;
    // The row's backward projections first, in a loop that vectorises (holes too: not read).
    static thread_local std::vector<double> sourceU, sourceV;
    static thread_local std::vector<uint8_t> sourceOk;
    sourceU.resize(size_t(width));
    sourceV.resize(size_t(width));
    sourceOk.resize(size_t(width));
    // Their addresses in locals: a thread_local vector's would be looked up again for every sample.
    double* us = sourceU.data();
    double* vs = sourceV.data();
    uint8_t* ok = sourceOk.data();
    for (int y = y0; y < y1; ++y) {
      projection.backwardRow(depth + size_t(y) * width, width, y, us, vs, ok);
      for (int x = 0; x < width; ++x) {
        const size_t i = size_t(y) * width + x;
        if (depth[i] < 0) continue;
        const double u = us[x], v = vs[x];
        if (!ok[x] || u < -0.5 || v < -0.5 || u > referenceWidth - 0.5 || v > referenceHeight - 0.5) {
          depth[i] = kNoDepth;
          continue;
        }
        long long row;
        if (sampler.wholeRow(v, row) && row == y) {
          if (tableRow != y) {
            for (int c = 0; c < channels; ++c) sampledRows[c].build<kTaps>(sampler, *planes[size_t(c)], y, -1, referenceWidth);
            tableRow = y;
          }
          for (int c = 0; c < channels; ++c) colour[c][i] = sampledRows[c].at<kTaps>(u);
        } else {
          for (int c = 0; c < channels; ++c) colour[c][i] = sampler.sampleTaps<kTaps>(*planes[size_t(c)], u, v);
        }
        const int eu = std::clamp(int(std::floor(u + 0.5)), 0, referenceWidth - 1);
        const int ev = std::clamp(int(std::floor(v + 0.5)), 0, referenceHeight - 1);
        edgeOut[i] = edges[size_t(ev) * referenceWidth + eu];
      }
    }
  });
  });
}

void Synthesizer::removeBoundaryNoise(ViewState& view) {
  WarpedLayer& layer = view.luma;
  // Samples on a reference depth edge within two samples of this view's own hole carry foreground
  // colour bled onto background: drop them, so the other view or the hole filler supplies them.
  const int w = layer.width, h = layer.height;
  std::vector<uint8_t>& drop = view.dropScratch;
  drop.assign(size_t(w) * h, 0);
  parallelRanges(h, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < w; ++x) {
        if (!layer.edge[size_t(y) * w + x] || layer.inverseDepth[size_t(y) * w + x] < 0) continue;
        bool nearHole = false;
        for (int ny = std::max(0, y - 2); ny <= std::min(h - 1, y + 2) && !nearHole; ++ny)
          for (int nx = std::max(0, x - 2); nx <= std::min(w - 1, x + 2); ++nx) nearHole |= layer.inverseDepth[size_t(ny) * w + nx] < 0;
        drop[size_t(y) * w + x] = nearHole;
      }
  });
  for (size_t i = 0; i < drop.size(); ++i)
    if (drop[i]) layer.inverseDepth[i] = kNoDepth;
}

void Synthesizer::rejectOccludedInOtherViews() {
  // A sample only one view shows fills a hole of the other views; one farther than the surroundings
  // every other view shows there is a misplaced one (Occlusion.h).
  std::vector<WarpedLayer*> layers;
  for (ViewState& view : views_) layers.push_back(&view.luma);
  rejectMisplacedSamples(layers, blendOptions_.weights, kBehindHoleSteps * discontinuity_, occlusionScratch_);
}

void Synthesizer::warpChroma(ViewState& view, const Frame& texture) {
  const int cw = chromaWidth(outputFormat_.width, outputFormat_.chroma);
  const int ch = chromaHeight(outputFormat_.height, outputFormat_.chroma);
  const WarpedLayer& luma = view.luma;
  WarpedLayer& layer = view.chroma;
  layer.resize(cw, ch, 2);  // cleared row by row below (clearRows)
  const double tolerance = fillOptions_.depthTolerance;
  // The block size (2 for 4:2:0, 1 for 4:4:4) and the kernel as compile-time constants: the block
  // loops unroll and the division by the block size is exact as a multiplication.
  auto warp = [&](auto blockSize, auto taps) {
    constexpr int kBlock = decltype(blockSize)::value, kTaps = decltype(taps)::value;
    parallelRanges(ch, [&](int j0, int j1) {
      // Locals, as in warpTexture: the byte and double stores below could alias what the loop reads.
      const ViewProjection projection = view.projection;
      const SubPixelSampler sampler = sampler_;
      const int lumaWidth = luma.width, lumaHeight = luma.height, chromaW = cw, chromaH = ch;
      const double surface = tolerance;
      const double* lumaDepth = luma.inverseDepth.data();
      const uint8_t* lumaEdge = luma.edge.data();
      double* depthOut = layer.inverseDepth.data();
      uint8_t* edgeOut = layer.edge.data();
      float* uOut = layer.colour[0].data();
      float* vOut = layer.colour[1].data();
      const bool rows = parallel_;
      // Chroma sample centres sit in the middle of their luma block (doc/formats-yuv.md).
      const double offset = 0.5 * (kBlock - 1);
      // 1D: each reference chroma row sampled once at every grid position (SampledRow, as in
      // warpTexture); positions in [-1, chromaW] have integer parts in [-1, chromaW].
      static thread_local SampledRow sampledRowU, sampledRowV;
      SampledRow &sampledU = sampledRowU, &sampledV = sampledRowV;  // the thread's, looked up once
      // A row's block depths and edges first; then its source positions (and on the 1D path its grid
      // indices) in passes that vectorise (as in warpTexture), before the look-ups.
      static thread_local std::vector<double> blockDepthRow, sourceRow, sourceVRow, gridRow;
      static thread_local std::vector<uint8_t> blockEdgeRow, sourceOkRow;
      for (auto* buffer : {&blockDepthRow, &sourceRow, &sourceVRow, &gridRow}) buffer->resize(size_t(chromaW));
      for (auto* buffer : {&blockEdgeRow, &sourceOkRow}) buffer->resize(size_t(chromaW));
      double* sourcesV = sourceVRow.data();
      uint8_t* sourceOk = sourceOkRow.data();
      double* blockDepth = blockDepthRow.data();
      double* sources = sourceRow.data();
      double* grid = gridRow.data();
      uint8_t* blockEdge = blockEdgeRow.data();
      int tableRow = -1;  // the row sampledU and sampledV hold (the general path builds them when needed)
      for (int j = j0; j < j1; ++j) {
        clearRows(layer, j, j + 1);
        if (rows) {
          sampledU.build<kTaps>(sampler, texture.planes[1], j, -1, chromaW);
          sampledV.build<kTaps>(sampler, texture.planes[2], j, -1, chromaW);
          tableRow = j;
        }
        // The chroma sample covers a block x block square of luma samples; it takes the depth of the
        // front-most surface there (the mean inverse depth of the block's samples on it). Luma samples
        // beyond the picture (an odd size) are not part of the block (bw x bh of it are inside): they
        // read as holes here, which neither the maximum nor the sum below takes.
        auto block = [&](int i, int bw, int bh) __attribute__((always_inline)) {
          const size_t corner = size_t(j) * kBlock * lumaWidth + size_t(i) * kBlock;
          double depths[kBlock * kBlock];
          uint8_t edges[kBlock * kBlock];
          double front = kNoDepth;
          for (int dy = 0; dy < kBlock; ++dy)
            for (int dx = 0; dx < kBlock; ++dx) {
              const bool inside = dx < bw && dy < bh;
              const size_t k = corner + size_t(dy) * lumaWidth + size_t(dx);
              depths[dy * kBlock + dx] = inside ? lumaDepth[k] : kNoDepth;
              edges[dy * kBlock + dx] = inside ? lumaEdge[k] : 0;
              front = std::max(front, depths[dy * kBlock + dx]);
            }
          // Without branches, in the same order: adding +0.0 leaves the sum unchanged (it is never
          // -0.0, as it starts at +0.0 and only grows by non-negative depths). A block without a
          // sample (front < 0) is a hole.
          double sum = 0;
          int count = 0;
          uint8_t edge = 0;
          for (int k = 0; k < kBlock * kBlock; ++k) {
            const bool onFront = depths[k] >= 0 && front - depths[k] <= surface;
            sum += onFront ? depths[k] : 0.0;
            count += int(onFront);
            edge |= onFront ? edges[k] : uint8_t(0);
          }
          blockDepth[i] = front < 0 ? kNoDepth : sum / std::max(count, 1);
          blockEdge[i] = edge;
        };
        // Whole blocks first, in a loop whose body knows it (and which the compiler can vectorise),
        // then those the picture's edge cuts.
        const int whole = (j + 1) * kBlock <= lumaHeight ? std::min(chromaW, lumaWidth / kBlock) : 0;
        for (int i = 0; i < whole; ++i) block(i, kBlock, kBlock);
        for (int i = whole; i < chromaW; ++i)
          block(i, std::min(kBlock, lumaWidth - i * kBlock), std::min(kBlock, lumaHeight - j * kBlock));
        if (rows) {
          // backward() on a rectified pair: u = rowSource(x, wv), v = y; then cv is the integer j.
          projection.rowSources(blockDepth, chromaW, sources, kBlock, offset);
          for (int i = 0; i < chromaW; ++i) {
            sources[i] = (sources[i] - offset) / kBlock;
            grid[i] = sampledU.gridIndex(sources[i]);
          }
        } else {
          projection.backwardRow(blockDepth, chromaW, double(j * kBlock) + offset, sources, sourcesV, sourceOk, kBlock,
                                 offset);
        }
        for (int i = 0; i < chromaW; ++i) {
          const double inverseDepth = blockDepth[i];
          if (inverseDepth < 0) continue;
          const size_t c = size_t(j) * chromaW + i;
          if (rows) {
            const double cu = sources[i];
            if (!std::isfinite(cu) || cu < -1.0 || cu > chromaW) continue;
            depthOut[c] = inverseDepth;
            edgeOut[c] = blockEdge[i];
            uOut[c] = sampledU.atGrid<kTaps>(cu, grid[i]);
            vOut[c] = sampledV.atGrid<kTaps>(cu, grid[i]);
            continue;
          }
          if (!sourceOk[i]) continue;  // backward() refuses it
          const double u = sources[i], v = sourcesV[i];
          const double cu = (u - offset) / kBlock, cv = (v - offset) / kBlock;
          if (cu < -1.0 || cv < -1.0 || cu > chromaW || cv > chromaH) continue;
          depthOut[c] = inverseDepth;
          edgeOut[c] = blockEdge[i];
          // As in warpTexture: a look-up on this row's own reference row reads the row's table.
          long long row;
          if (sampler.wholeRow(cv, row) && row == j) {
            if (tableRow != j) {
              sampledU.build<kTaps>(sampler, texture.planes[1], j, -1, chromaW);
              sampledV.build<kTaps>(sampler, texture.planes[2], j, -1, chromaW);
              tableRow = j;
            }
            uOut[c] = sampledU.at<kTaps>(cu);
            vOut[c] = sampledV.at<kTaps>(cu);
            continue;
          }
          uOut[c] = sampler.sampleTaps<kTaps>(texture.planes[1], cu, cv);
          vOut[c] = sampler.sampleTaps<kTaps>(texture.planes[2], cu, cv);
        }
      }
    });
  };
  sampler_.withTaps([&](auto taps) {
    if (outputFormat_.chroma == ChromaFormat::Yuv420) warp(std::integral_constant<int, 2>(), taps);
    else warp(std::integral_constant<int, 1>(), taps);
  });
}

void Synthesizer::keepStaticFill(const std::vector<ReferenceFrame>& references, std::vector<uint8_t>& lumaHoles,
                                 std::vector<uint8_t>& chromaHoles) {
  // TemporalImprovementOption: hole filling guesses; where a row of every reference is unchanged
  // since the previous frame, a sample that was a hole then and is one now keeps the previous guess,
  // so static disocclusions do not flicker. This frame's holes become the previous ones (swapped: the
  // caller refills its buffer next frame), and its filled colours are kept (only the colours: the
  // rest of the layer is not needed).
  const int h = outputFormat_.height, w = outputFormat_.width;
  std::vector<uint8_t> rowStatic(size_t(h), havePrevious_ ? 1 : 0);
  if (havePrevious_)
    parallelRanges(h, [&](int y0, int y1) {
      for (size_t k = 0; k < references.size(); ++k)
        for (int y = y0; y < y1; ++y)
          rowStatic[size_t(y)] &= uint8_t(std::equal(references[k].depth->row(y), references[k].depth->row(y) + w,
                                                     previousDepth_[k].row(y)) &&
                                          std::equal(references[k].texture->planes[0].row(y),
                                                     references[k].texture->planes[0].row(y) + w, previousLuma_[k].row(y)));
    });
  auto keep = [&](BlendedLayer& layer, std::vector<uint8_t>& holes, std::vector<uint8_t>& previousHoles,
                  std::vector<float>* previousColour, int rowsPerSample) {
    if (havePrevious_ && previousHoles.size() == holes.size())
      parallelRanges(layer.height, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
          bool unchanged = true;
          for (int r = y * rowsPerSample; r < std::min(h, (y + 1) * rowsPerSample); ++r) unchanged = unchanged && rowStatic[size_t(r)];
          if (!unchanged) continue;
          for (int x = 0; x < layer.width; ++x) {
            const size_t i = size_t(y) * layer.width + x;
            if (holes[i] && previousHoles[i])
              for (int c = 0; c < layer.channels; ++c) layer.colour[c][i] = previousColour[c][i];
          }
        }
      });
    previousHoles.swap(holes);
    for (int c = 0; c < layer.channels; ++c) copyOnThreads(layer.colour[c], previousColour[c]);
  };
  keep(blendedLuma_, lumaHoles, previousHoles_, previousColour_, 1);
  if (!rgb_ && hasChroma_)
    keep(blendedChroma_, chromaHoles, previousChromaHoles_, previousChromaColour_,
         outputFormat_.chroma == ChromaFormat::Yuv420 ? 2 : 1);
  previousDepth_.resize(references.size());
  previousLuma_.resize(references.size());
  auto keepPlane = [](const Plane& from, Plane& to) {
    to.width = from.width;
    to.height = from.height;
    copyOnThreads(from.samples, to.samples);
  };
  for (size_t k = 0; k < references.size(); ++k) {
    keepPlane(*references[k].depth, previousDepth_[k]);
    keepPlane(references[k].texture->planes[0], previousLuma_[k]);
  }
  havePrevious_ = true;
}

void Synthesizer::virtualDepth(const DepthRange& range, Plane& levels) const {
  const int w = outputFormat_.width, h = outputFormat_.height;
  levels.resize(w, h);
  const Camera& camera = scene_.virtualCamera;
  parallelRanges(h, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < w; ++x) {
        const double inverse = blendedLuma_.inverseDepth[size_t(y) * w + x];
        double z = inverse > 0 ? 1.0 / inverse : HUGE_VAL;
        if (scene_.settings.depthType == 1 && std::isfinite(z)) z = camera.backProject(x, y, z).z;  // world z
        levels.at(x, y) = inverse < 0 ? 0 : uint16_t(zToLevelRounded(z, range));
      }
  });
}

bool Synthesizer::viewsSideBySide() const {
  const size_t count = views_.size();
  const int threads = cv::getNumThreads();
  return count >= 2 && threads >= 2 && count % size_t(threads) == 0;
}

template <class Step>
void Synthesizer::forEachView(const Step& step) {
  // With as many views per thread on every thread (two views, two threads: the usual case), each
  // thread runs whole views: one hand-over per stage instead of one per loop inside it, and no thread
  // waits at the end of every loop for the other's last rows. The loops inside then run on the
  // calling thread (OpenCV runs a parallel_for_ inside another one sequentially). Each view's steps
  // write only that view's state, so the output is the same either way.
  const size_t count = views_.size();
  if (viewsSideBySide()) {
    parallelRanges(int(count), [&](int k0, int k1) {
      for (int k = k0; k < k1; ++k) step(size_t(k));
    });
    return;
  }
  for (size_t k = 0; k < count; ++k) step(k);
}

void Synthesizer::synthesize(const std::vector<ReferenceFrame>& references, Frame& output, StageTimes& times) {
  VS_CHECK(references.size() == views_.size());
  output.reset(outputFormat_);
  auto start = std::chrono::steady_clock::now();
  const SynthesisSettings& s = scene_.settings;
  std::vector<const Plane*> lumas;
  for (const ReferenceFrame& reference : references) lumas.push_back(&reference.texture->planes[0]);
  auto depthSteps = [&](size_t k) {
    ViewState& view = views_[k];
    const Plane* depth = references[k].depth;
    const bool filled = s.missingDepthLevel >= 0 && s.missingDepthFill;
    if (filled) {
      // Missing runs between valid samples take the farther level; the inverse-depth table has NaN
      // at the missing level, which fillMissingDepthRuns never picks (both ends are valid).
      fillMissingDepthRuns(*depth, s.missingDepthLevel, view.levelToInverseDepth, view.filledDepth, view.filledSamples);
      depth = &view.filledDepth;
    }
    view.alignedSamples = 0;
    depth = &aligner_.align(k, *depth, lumas, view.alignedSamples);
    markReferenceEdges(view, *depth);
    // Estimated depth is unreliable: where another view has a real one on the same surface, it wins
    // (also where alignment then gave a filled sample the near side's level).
    if (filled)
      for (size_t i = 0; i < view.referenceEdge.size(); ++i) view.referenceEdge[i] |= view.filledSamples[i];
    warpDepth(view, *depth);
  };
  forEachView(depthSteps);
  stats_.alignedDepthSamples = 0;
  for (const ViewState& view : views_) stats_.alignedDepthSamples += view.alignedSamples;
  times.depthWarp += secondsSince(start);

  start = std::chrono::steady_clock::now();
  if (rgb_) rgbReferences_.resize(views_.size());
  forEachView([&](size_t k) {
    ViewState& view = views_[k];
    const Frame& texture = *references[k].texture;
    if (rgb_) {
      yuvToRgb(texture, rgbReferences_[k]);
      warpTexture(view, {&rgbReferences_[k].planes[0], &rgbReferences_[k].planes[1], &rgbReferences_[k].planes[2]});
    } else {
      warpTexture(view, {&texture.planes[0]});
    }
    if (scene_.settings.boundaryNoiseRemoval) removeBoundaryNoise(view);
    if (parallel_ && scene_.settings.oneD.merging == 2) flagCrowdedHoles(view);
  });
  if (views_.size() > 1) rejectOccludedInOtherViews();
  // Chroma follows the luma decisions: it is warped from the final luma depth.
  if (!rgb_ && hasChroma_) forEachView([&](size_t k) { warpChroma(views_[k], *references[k].texture); });
  times.textureWarp += secondsSince(start);

  start = std::chrono::steady_clock::now();
  std::vector<const WarpedLayer*> lumaLayers, chromaLayers;
  for (const ViewState& view : views_) {
    lumaLayers.push_back(&view.luma);
    chromaLayers.push_back(&view.chroma);
  }
  blendLayers(lumaLayers, blendOptions_, blendedLuma_);
  if (!rgb_ && hasChroma_) blendLayers(chromaLayers, blendOptions_, blendedChroma_);
  stats_.holesAfterBlend = blendedLuma_.holeCount();
  times.blend += secondsSince(start);

  start = std::chrono::steady_clock::now();
  const bool temporal = parallel_ && scene_.settings.oneD.temporalImprovement;
  std::vector<uint8_t>& lumaHoles = lumaHolesScratch_;
  std::vector<uint8_t>& chromaHoles = chromaHolesScratch_;
  if (temporal) {
    copyOnThreads(blendedLuma_.hole, lumaHoles);  // same size every frame: no allocation once grown
    copyOnThreads(blendedChroma_.hole, chromaHoles);
  }
  HoleFillOptions chromaFill = fillOptions_;
  chromaFill.emptyValue[0] = chromaFill.emptyValue[1] = fillOptions_.emptyValue[1];
  std::vector<HoleFillJob> fills = {{&blendedLuma_, &fillOptions_, &lumaFill_}};
  if (!rgb_ && hasChroma_) fills.push_back({&blendedChroma_, &chromaFill, &chromaFill_});
  fillHoles(fills);
  if (temporal) keepStaticFill(references, lumaHoles, chromaHoles);
  times.holeFill += secondsSince(start);

  roundLayersToFrame(blendedLuma_, blendedChroma_, rgb_, rgbOutput_, output);
}

}  // namespace vs
