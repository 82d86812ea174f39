#pragma once
// A file's analysis stages refined alike (ReadOptions::refine, core::refineModel): every flexible
// beam of every stage split in the same parts, so the stages keep one topology and one numbering.
#include <vector>

#include "io/formats/DatReader.hpp"

namespace flexmb::io {

// Refines every stage in place with options.refine parts (1: nothing changes), the elements
// created as the reader created them (options.elongation, else the dialect's default). Each model
// gets the summary ("refined: every flexible beam split in 8 (85 elements, 86 nodes)") and every beam
// left whole as notes; options.refinedResults drops Model::unrefined (results of every node). Throws DatError (the
// file, line 0) for a refinement below 1 or a model that cannot be refined (a restart state).
void refineStages(std::vector<AnalysisStage>& stages, const ReadOptions& options);

}  // namespace flexmb::io
