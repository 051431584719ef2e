#pragma once
// Telea's fast-marching inpainting (A. Telea, "An image inpainting technique based on the fast
// marching method", J. Graphics Tools 9(1), 2004), in two forms (doc/algorithms.md, "Hole filling"):
//
// likeOpenCv (the hole filling's chroma): exactly what OpenCV 4.6's (Debian 12's)
// cv::inpaint(src, mask, dst, radius, cv::INPAINT_TELEA) computes for a CV_32FC1 image, bit for bit,
// for several planes in one march:
//   - the same arrival times: a march outwards over the known samples within `radius` of the mask
//     (their times are negative), then the inward march that fills;
//   - the same order: samples leave the queue by arrival time, equal times in the order they entered
//     (OpenCV's queue is a sorted list whose every insert walks it; here the band, which enters
//     first at time 0, is read in order and a 4-ary heap holds the rest: the same order at a
//     logarithmic cost);
//   - the same float and double arithmetic, expression by expression, and the same quirks: a
//     neighbour in the picture's first row or column reads its colour from the second, a central
//     difference of colour is doubled, and 0.5 is added to every filled value (meant for rounding
//     to 8 bits, kept for floats);
//   - the weights of a neighbour depend only on the mask and the arrival times, so one march serves
//     every plane: each plane's sums are accumulated in OpenCV's order.
// Test/Unit/TeleaTest.cpp compares it with cv::inpaint on random pictures and masks.
//
// Otherwise (the hole filling's luma, and R, G, B): the inward march alone, every known sample at
// time 0 (no outward march), and the filled value the weighted mean of the known neighbours, with
// the same weights (distance, level set, direction) and order, plus the same 0.5; OpenCV's
// colour-gradient term (J_x + J_y) / |J|, a value within +-sqrt(2) from the neighbours' colour
// gradients, is left out. Cheaper (no ring to find and march, no gradient read per neighbour), and
// as good or better in the hole filling's mix (doc/speed.md, 2026-11-26, "Luma's inpainting without
// OpenCV's outward march"). Test/Unit/TeleaReference.h is its plain implementation, the tests' truth.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vs {

// A neighbour within the radius: its offset, its position relative to the centre as OpenCV's
// r = centre - neighbour, and the distance weight 1 / |r|^3.
struct TeleaOffset {
  int dRow, dCol;
  float rx, ry, distance;
};

// Reused working memory of teleaInpaint (one per thread).
struct TeleaScratch {
  std::vector<uint8_t> flags, outer, knownSides;
  std::vector<float> time;
  std::vector<uint8_t> rowCount;    // the outer ring's window counts
  std::vector<uint8_t> rowSpan;     // one row's window flags, padded
  std::vector<uint64_t> queue;     // arrival time and push count
  std::vector<uint32_t> positions;  // grid position of each push
  std::vector<uint32_t> band;       // the known samples beside the mask, where both marches start
                                    // (its first entries: it is sized to the largest grid)
  std::vector<TeleaOffset> offsets;
  std::vector<ptrdiff_t> gridOffset, sampleOffset;
  std::vector<uint16_t> known;
  std::vector<float> offsetLanes;   // the offsets' rx, ry and distance, neighbour times, weights
};

// Inpaints, in place, four float planes of width x height, interleaved: sample (row, col) of plane p
// is samples[(row * rowStride + col) * 4 + p]. The planes are filled where `mask` (row stride
// `maskStride` bytes) is non-zero, each as if it were filled alone (the planes are computed side by
// side, lane by lane: a plane not needed can hold zeros). `radius` as cv::inpaint's
// (rounded, clamped to 1..100). A picture one sample high or wide, where OpenCV reads outside its
// image, is filled from its own samples.
// likeOpenCv: cv::inpaint's result bit for bit; otherwise the cheaper weighted mean (above).
void teleaInpaint(const uint8_t* mask, size_t maskStride, int width, int height, float* samples, size_t rowStride,
                  double radius, TeleaScratch& scratch, bool likeOpenCv = true);

}  // namespace vs
