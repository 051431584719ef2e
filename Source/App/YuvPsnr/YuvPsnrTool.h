#pragma once
// YuvPsnr's parser and run (YuvPsnrTool.cpp): main.cpp hands it the command line.

// Parses argv (problems: exit code 2), compares the files, prints the table; returns the exit code.
int yuvPsnrMain(int argc, char** argv);
