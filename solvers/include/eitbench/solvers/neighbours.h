#pragma once
// Whose neighbours a regularising prior couples (the Laplace prior, total variation): the image's
// pixels (4-neighbour), or the mesh's triangles (those sharing an edge), applied to the elements'
// values P x.
#include <string>

namespace eitbench {

enum class Neighbours { pixels, elements };
// pixels | elements; InputError("Neighbours", "name") for another name.
Neighbours parse_neighbours(const std::string& name);

}  // namespace eitbench
