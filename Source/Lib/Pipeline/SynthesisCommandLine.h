#pragma once
// ViewSyn's and MeshRender's command line, on the shared front (Common/CommandLine.h):
//   TOOL FILE.cfg [Key=Value ...] [--verify MD5]   run; with --verify the output file's MD5 must be MD5
//                                                  afterwards (else exit 1 with both digests)
//   TOOL --check FILE.cfg [Key=Value ...]          check config and camera file, open no YUV file
//   TOOL --print-config FILE.cfg [Key=Value ...]   the effective config and the scene as JSON
//   TOOL --help | --help-markdown
#include <functional>
#include <string>

#include "Common/CommandLine.h"
#include "Common/Config.h"
#include "Common/Scene.h"

namespace vs {

struct SynthesisTool {
  std::string name;
  std::string description;  // what the tool does, for --help
  std::string checkHelp;    // what --check checks, one line
  std::string manual;       // "doc/manual.md"
  const OptionTable* keys = nullptr;
  std::function<void(const Config&)> run;  // renders the sequence (throws InputError)
  // --check's and --print-config's checks beyond the scene (may be null); prints what it found to
  // `out` when `out` is not null.
  std::function<void(const Config&, std::FILE* out)> check;
};

CommandLineTool synthesisCommandLine(const SynthesisTool& tool);

}  // namespace vs
