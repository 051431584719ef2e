#pragma once
// YuvPsnr's option table and run (YuvPsnrTool.cpp), for the shared command-line front.
#include "Common/CommandLine.h"

// The tool: options, usage text, positional check and run, for vs::runCommandLine().
vs::CommandLineTool yuvPsnrTool();
