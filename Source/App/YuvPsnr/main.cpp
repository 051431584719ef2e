// YuvPsnr: PSNR, and on request IV-PSNR, WS-PSNR, SSIM and MS-SSIM (doc/metrics.md), of a test YUV
// file against a reference, frame by frame and averaged (doc/formats-yuv.md). The tool is in
// YuvPsnrTool.cpp. Exit codes: 0 done, 1 file error, 2 bad arguments.
#include "Common/CommandLine.h"
#include "YuvPsnrTool.h"

int main(int argc, char** argv) { return vs::runCommandLine(argc, argv, yuvPsnrTool()); }
