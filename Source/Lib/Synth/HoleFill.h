#pragma once
// Filling what no reference view sees (doc/algorithms.md, "Hole filling").
//
// Holes are disoccluded background. With IvsrsInpaint 1 three background-only estimates are mixed
// 2 : 3 : 1 over those that reach a sample:
//   - directional: each hole sample looks in eight directions for the nearest sample with colour,
//     keeps those on the farthest surface found (within the depth tolerance) and mixes them by
//     inverse distance; it keeps texture but copies it in streaks;
//   - row runs (after iVSRS in VSRS 4.x): each run of holes along a row takes the mean colour of the
//     candidates on the farthest surface among its ends and the first samples along seven rays up
//     and down from its middle; one colour per run;
//   - inpainting: Telea's inpainting (Synth/Telea.h) of the holes; with
//     HoleFillOptions::inpaintNearerSurface (the plan's chroma setting) the nearer surface around
//     each hole is masked and inpainted too, so that only background propagates. Luma inpaints the
//     holes alone: a higher PSNR on the Middlebury scenes, and less to fill. With
//     HoleFillOptions::inpaintLikeOpenCv (chroma) it is OpenCV's result bit for bit; without it
//     (luma) the cheaper weighted mean from the inward march alone.
// The mix has a lower error than any one of them on the Middlebury scenes (doc/algorithms.md).
// IvsrsInpaint 0: Telea inpainting of the holes alone, as VSRS does (VSRS calls OpenCV's; luma
// here the weighted mean without OpenCV's outward march and colour-gradient term). A layer
// without any valid sample is filled with `emptyValue`.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "Synth/Layer.h"
#include "Synth/ScratchPool.h"
#include "Synth/Telea.h"

namespace vs {

// A rectangle of samples (or blocks): its first column and row, width and height.
struct SampleBox {
  int x = 0, y = 0, width = 0, height = 0;
  int area() const { return width * height; }
};

// Working buffers of fillHoles, kept by a caller that fills every frame so that nothing is allocated
// per frame once they have grown to the picture's size.
struct HoleFillScratch {
  // Where each hole sample's estimates are: the hole samples one after another in raster order, a
  // hole's place the number of holes before it. Stored per hole instead of per picture sample, the
  // estimates take what the holes need (the 1920x1080 demo's few per cent of the samples) and lie
  // together, where a picture-sized buffer written at the holes only made a 4 KiB page resident per
  // row of every hole's column (doc/speed.md, fifth round).
  struct HolePlaces {
    static constexpr int kBlock = 64;  // samples per block of a row
    int width = 0, blocksPerRow = 0;
    size_t count = 0;                  // hole samples in the layer
    std::vector<size_t> before;        // per row and block: the holes before its first sample
    // Counts the holes of `hole` (width x height, non-zero: a hole).
    void index(const std::vector<uint8_t>& hole, int width, int height);
    // The place of the first hole at or after column x of row y (x <= width).
    size_t at(const uint8_t* hole, int x, int y) const;
    size_t rowStart(int y) const { return before[size_t(y) * size_t(blocksPerRow)]; }
  } places;
  // The estimates, by hole place (`places`): written and read at hole samples only.
  UntouchedBuffer<float> directional[3], runs[3], inpainted[3];
  UntouchedBuffer<double> background, runBackground;
  UntouchedBuffer<uint8_t> found, runFound;
  std::vector<uint8_t> mask;                   // the background-only mask (inpaintNearerSurface)
  const std::vector<uint8_t>* inpaintMask = nullptr;  // what is inpainted: `mask` or the layer's holes
  struct InpaintGroups {  // the inpainting's groups of holes, by blocks (HoleFill.cpp)
    int columns = 0, rows = 0;
    std::vector<int> label;
    std::vector<SampleBox> extent;
    std::vector<int> stack;
  } inpaintGroups;
  struct InpaintTask {    // one group of holes and its crop, to inpaint
    int group;
    SampleBox crop;
  };
  std::vector<InpaintTask> tasks;
  // Working buffers of the parallel loop bodies, one set per body running at once (ScratchPool.h).
  ScratchPool<std::vector<int>> columnRows;  // the directional fill's per-column rows
  struct Thresholds {                        // the background-only mask's thresholds of one row
    std::vector<double> run, span;
  };
  ScratchPool<Thresholds> thresholdRows;
  struct InpaintBuffers {                    // one group's inpainting
    TeleaScratch telea;
    std::vector<uint8_t> groupMask;
    std::vector<float> samples;              // the crop's channels, interleaved four to a sample
  };
  ScratchPool<InpaintBuffers> inpaintBuffers;
};

// Fills every hole of `layer` (hole mask cleared, inverse depth set to the background's where
// known). Returns the number of samples that were holes. `scratch`: reused buffers (nullptr: local).
size_t fillHoles(BlendedLayer& layer, const HoleFillOptions& options, HoleFillScratch* scratch = nullptr);

// Fills several layers (luma and chroma): the same result as fillHoles on each, with the inpainting
// of all of them shared among the threads (one layer's may be a single large group of holes).
struct HoleFillJob {
  BlendedLayer* layer;
  const HoleFillOptions* options;
  HoleFillScratch* scratch;
};
void fillHoles(const std::vector<HoleFillJob>& jobs);

}  // namespace vs
