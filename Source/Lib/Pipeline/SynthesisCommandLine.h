#pragma once
// ViewSyn's and MeshRender's command line, on the shared front (Common/CommandLine.h):
//   TOOL FILE.cfg [Key=Value ...] [--verify MD5]   run; with --verify the output file's MD5 must be MD5
//                                                  afterwards (else exit 1 with both digests)
//   TOOL --check FILE.cfg [Key=Value ...]          check config, camera file, every input file (type,
//                                                  format, size) and every output name; write nothing
//   TOOL --print-config FILE.cfg [Key=Value ...]   the effective config and the scene as JSON
//   TOOL --help | --help-markdown
#include <cstdio>
#include <functional>
#include <string>

#include "Common/CommandLine.h"
#include "Common/Config.h"
#include "Common/InputCheck.h"
#include "Common/Scene.h"

namespace vs {

struct SynthesisTool {
  std::string name;
  std::string description;  // what the tool does, for --help
  std::string checkHelp;    // what --check checks, one line
  std::string manual;       // "doc/manual.md"
  const OptionTable* keys = nullptr;
  std::function<void(const Config&)> run;  // renders the sequence (throws InputError)
  // The tool's own checks beyond config and scene for --check and --print-config (may be null):
  // throws InputError for what a run would refuse; called before anything is printed.
  std::function<void(const Config&, const Scene&)> validate;
  // Files the tool writes besides the scene's outputs (MeshRender's PLY files; may be null): --check
  // checks them with the outputs (Common/InputCheck.h, checkOutputs).
  std::function<std::vector<NamedOutput>(const Config&, const Scene&)> extraOutputs;
  // --check only: what the tool adds to the printout after the cameras (may be null; may throw).
  std::function<void(std::FILE* out)> describe;
};

CommandLineTool synthesisCommandLine(const SynthesisTool& tool);

}  // namespace vs
