// A check of a PLY file's layout before assimp reads it (mesh_import.cpp). assimp 5.2, the
// version Debian 12 ships, trusts a PLY file's counts:
// - it loops forever on a header cut off inside a property line, and on one that ends in
//   "end_header" without a newline when the header holds a line it does not know;
// - it writes past its arrays when a header declares a second vertex list or a second face list,
//   and reads past a face's vertex list when the face has more than two texture coordinates per
//   vertex (both seen by valgrind inside libassimp);
// - it allocates what a count asks for before it reads the data: a 150-byte file that declares
//   300 million vertices took 3.5 GB and over 20 s, a face list of length "344...4" over 6 GB;
// - it reads an element's count from the digits after the name, or from a name that starts
//   with a digit, and ends a header line at '\r', '\f' or '\0' too: "element 30000000face 1"
//   took 700 MB and two minutes, a fuzz input's element name of 26 nines asked for 92 GB; and
//   a property of a type PLY does not have, or a format it does not have, lets assimp allocate
//   without reading (3.5 GB; all the memory there was).
// Each was found by the fuzz targets (tests/fuzz) or in following up their findings. This check
// reads the header and walks the data as the header lays it out (ASCII as assimp reads it, an
// entry per line), converting no value but a list's length, and refuses a file whose data cannot
// hold what its header declares, naming the entry. Its header must be text (no control
// characters), one of PLY's three formats, element lines "element NAME COUNT" and properties
// of PLY's types after an element, so that both read the same layout.
//
// It is not a PLY reader: it refuses only what no well-formed file is, and leaves the rest
// (the values themselves, lines it does not know) to assimp.
#pragma once

#include <string>

namespace vf {

// Throws InputError naming the file (and the line for a fault in the header or in ASCII data)
// when `path` is a PLY file (it starts with "ply", or its name ends in .ply) with one of the
// faults above. Other files are not read beyond their first three bytes.
void checkPlyLayout(const std::string& path);

}  // namespace vf
