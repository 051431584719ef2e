#pragma once
// The option tables of the executables. ViewSyn's table holds every key VSRS 4.2 reads, with VSRS's
// meaning, plus ours; MeshRender's is ViewSyn's plus the mesh keys.
#include "Common/Config.h"

namespace vs {

// Keys every synthesizer reads (VSRS 4.2's keys and our additions).
void addSynthesisOptions(OptionTable& table);
// Keys only MeshRender reads.
void addMeshOptions(OptionTable& table);

OptionTable viewSynOptionTable();
OptionTable meshRenderOptionTable();

}  // namespace vs
