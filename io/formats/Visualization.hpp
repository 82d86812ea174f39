#pragma once
// The VISUALIZATION section at the end of a .dat file (SPACAR Light, oopspa and SPAVISUAL write it):
// drawing hints per element, read into core::Model::appearance. Statements, one per line:
//   BEAMPROPS e1 e2 ...      the elements the following CROSSTYPE / CROSSDIM describe
//   CROSSTYPE RECT | CIRC    cross-section shape
//   CROSSDIM w t | d         rectangle width (along the local y axis) and thickness, circle diameter
//   GRAPHICS e1 e2 ...       the elements the following FACECOLOR / OPACITY describe
//   FACECOLOR r g b          colour, components 0..1
//   OPACITY a                0..1
//   DONOTDRAW e1 e2 ...      elements left out of the pictures
//   INITIAL, COLOR r g b     the colour of the initial configuration (accepted, not used)
// The section never stops an analysis: anything it cannot use (an unknown statement, a number out of
// range, an element the model does not have) becomes a note naming the file and line.
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/model/Model.hpp"

namespace flexmb::io {

struct VisualizationSection {
  std::map<int, core::ElementAppearance> appearance;  // by element label
  std::vector<std::string> notes;
};

// text: the lines after the VISUALIZATION keyword, the first of them being line firstLine of file.
VisualizationSection parseVisualization(std::string_view text, int firstLine, const std::string& file);

// The statements above, for `flexmb keywords` and io/dat-language.md: (keyword, meaning).
const std::vector<std::pair<std::string, std::string>>& visualizationKeywords();

}  // namespace flexmb::io
