// See ply_check.h. The PLY layout (Greg Turk's format, as assimp reads it): a text header of
// "element NAME COUNT" lines, each followed by its "property TYPE NAME" and "property list
// COUNT_TYPE ITEM_TYPE NAME" lines, up to "end_header"; then the data, entry after entry of each
// element in the header's order, each entry its properties in order, a list as its length and
// then that many values. ASCII data is whitespace-separated numbers (assimp reads an entry per
// line); binary data is packed, little- or big-endian.
#include "sim/geometry/ply_check.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string_view>
#include <vector>

#include "sim/core/error.h"

namespace vf {

namespace {

struct Property {
  std::string name;
  bool list = false;
  int size = 0;       // bytes of a value in binary data
  int countSize = 0;  // a list's length: its bytes in binary data
  bool countSigned = false;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Format { kUnknown, kAscii, kLittleEndian, kBigEndian };

// A PLY scalar type (both spellings of the format's two versions).
struct Type {
  const char* name;
  int size;  // bytes in binary data
  bool isInteger;
  bool isSigned;
};

constexpr Type kTypes[] = {
    {"char", 1, true, true},    {"uchar", 1, true, false},  {"short", 2, true, true},
    {"ushort", 2, true, false}, {"int", 4, true, true},     {"uint", 4, true, false},
    {"float", 4, false, true},  {"double", 8, false, true}, {"int8", 1, true, true},
    {"uint8", 1, true, false},  {"int16", 2, true, true},   {"uint16", 2, true, false},
    {"int32", 4, true, true},   {"uint32", 4, true, false}, {"float32", 4, false, true},
    {"float64", 8, false, true}};

// The type of that name; size 0 when PLY has none.
Type typeNamed(const std::string& name) {
  for (const Type& t : kTypes)
    if (name == t.name) return t;
  return {"", 0, false, false};
}

// PLY's type names, for a message.
std::string typeNames() {
  std::string names;
  for (const Type& t : kTypes) names += (names.empty() ? "" : ", ") + std::string(t.name);
  return names;
}

// A header line for a message: bytes outside printable ASCII as '?', at most 60 of them.
std::string printable(const std::string& line) {
  std::string s = line.substr(0, 60);
  for (char& c : s)
    if (c < ' ' || c > '~') c = '?';
  return line.size() > 60 ? s + "..." : s;
}

std::string entryOf(std::uint64_t i, const Element& e) {
  return "entry " + std::to_string(i + 1) + " of " + std::to_string(e.count) + " of element '" +
         e.name + "'";
}

[[noreturn]] void endsEarly(const std::string& where, std::uint64_t i, const Element& e) {
  throw InputError(where, "PLY data ends in " + entryOf(i, e) +
                              " (is the file cut off, or a count in it wrong?)");
}

[[noreturn]] void tooLong(const std::string& where, const Property& p, std::uint64_t i,
                          const Element& e, const std::string& length, const std::string& rest) {
  throw InputError(where, "PLY list '" + p.name + "' in " + entryOf(i, e) + " is " + length +
                              " long, more than " + rest);
}

// A face's texture coordinates, which assimp 5.2 pairs with its vertices by reading the vertex
// list at half the coordinate's index: more than two per vertex read past the face's vertex
// list (valgrind: "Invalid read" inside libassimp). voxfall reads no texture coordinates, but
// assimp reads them before voxfall sees the mesh.
class FaceTexcoords {
 public:
  explicit FaceTexcoords(const Element& e) {
    if (e.name != "face") return;
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const Property& p = e.properties[k];
      if (!p.list) continue;
      if (p.name == "vertex_indices" || p.name == "vertex_index") vertices_ = static_cast<int>(k);
      if (p.name == "texcoord") texcoords_ = static_cast<int>(k);
    }
  }
  // The length of the entry's k-th property, a list.
  void length(std::size_t k, std::int64_t n) {
    if (static_cast<int>(k) == vertices_) vertexCount_ = n;
    if (static_cast<int>(k) == texcoords_) texcoordCount_ = n;
  }
  // At the end of entry i: throws if it has more than two coordinates per vertex.
  void check(const std::string& where, std::uint64_t i, const Element& e) {
    if (texcoords_ >= 0 && texcoordCount_ > 2 * vertexCount_)
      throw InputError(where, "PLY " + entryOf(i, e) + " has " + std::to_string(texcoordCount_) +
                                  " texture coordinates for a vertex list of " +
                                  std::to_string(vertexCount_) + " (at most two per vertex)");
    vertexCount_ = texcoordCount_ = 0;
  }

 private:
  int vertices_ = -1, texcoords_ = -1;  // their properties' places; -1: none
  std::int64_t vertexCount_ = 0, texcoordCount_ = 0;
};

// ASCII data as assimp reads it: an entry per line.
class Lines {
 public:
  Lines(const std::string& text, std::size_t pos, int number)
      : s_(text), pos_(pos), number_(number - 1) {
    if (pos_ < s_.size())
      left_ = std::count(s_.begin() + pos_, s_.end(), '\n') + (s_.back() != '\n');
  }
  std::uint64_t left() const { return left_; }
  int number() const { return number_; }  // of the line last returned
  std::string_view next() {               // call only while left() > 0
    std::size_t end = s_.find('\n', pos_);
    if (end == std::string::npos) end = s_.size();
    const std::string_view line = std::string_view(s_).substr(pos_, end - pos_);
    pos_ = end + 1;
    ++number_;
    --left_;
    return line;
  }

 private:
  const std::string& s_;
  std::size_t pos_;
  int number_;
  std::uint64_t left_ = 0;
};

// The words of one line, in order.
std::vector<std::string_view> wordsOf(std::string_view line) {
  std::vector<std::string_view> words;
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  for (std::size_t i = 0; i < line.size();) {
    while (i < line.size() && blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !blank(line[i])) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

// The ASCII data against the header: as many lines as entries, and no list longer than the rest
// of its line (assimp sizes the list by its length before it looks for the values).
void checkAscii(const std::string& path, const std::string& text, std::size_t body, int bodyLine,
                const std::vector<Element>& elements) {
  Lines lines(text, body, bodyLine);
  for (const Element& e : elements) {
    if (e.count > lines.left()) {  // named at the file's last line
      const std::uint64_t whole = lines.left();
      endsEarly(sourceLocation(path, lines.number() + static_cast<int>(whole)), whole, e);
    }
    const bool hasList = std::any_of(e.properties.begin(), e.properties.end(),
                                     [](const Property& p) { return p.list; });
    FaceTexcoords texcoords(e);
    for (std::uint64_t i = 0; i < e.count; ++i) {
      const std::string_view line = lines.next();
      if (!hasList) continue;
      const std::vector<std::string_view> words = wordsOf(line);
      std::size_t w = 0;
      for (std::size_t k = 0; k < e.properties.size() && w < words.size(); ++k) {
        // (a short line: assimp fills in zeros)
        const Property& p = e.properties[k];
        const std::string_view word = words[w++];
        if (!p.list) continue;
        // The length's leading digits, as assimp reads it (none: 0); a number beyond 64 bits
        // is longer than any line.
        std::int64_t length = 0;
        const auto error = std::from_chars(word.data(), word.data() + word.size(), length).ec;
        if (error == std::errc::invalid_argument) length = 0;
        const std::size_t rest = words.size() - w;
        if ((error != std::errc() && error != std::errc::invalid_argument) || length < 0 ||
            static_cast<std::uint64_t>(length) > rest)
          tooLong(sourceLocation(path, lines.number()), p, i, e, std::string(word),
                  "the " + std::to_string(rest) + " numbers after it on its line");
        w += static_cast<std::size_t>(length);
        texcoords.length(k, length);
      }
      texcoords.check(sourceLocation(path, lines.number()), i, e);
    }
  }
}

// An element without properties takes no binary data. It could still make assimp allocate its
// count of entries: refused beyond one per byte of the file.
void checkEmptyElement(const std::string& path, const Element& e, std::size_t fileSize) {
  if (e.count > fileSize)
    throw InputError(path, "PLY element '" + e.name + "' declares " + std::to_string(e.count) +
                               " entries and no properties");
}

// A list length in binary data: an integer of p.countSize bytes, sign-extended if signed.
std::int64_t binaryLength(const unsigned char* b, const Property& p, bool bigEndian) {
  std::uint64_t v = 0;
  for (int k = 0; k < p.countSize; ++k) {
    const int byte = bigEndian ? k : p.countSize - 1 - k;
    v = (v << 8) | b[byte];
  }
  const int bits = 8 * p.countSize;  // 1, 2 or 4 bytes
  const bool negative = p.countSigned && (v >> (bits - 1)) != 0;
  return static_cast<std::int64_t>(v) - (negative ? std::int64_t{1} << bits : 0);
}

void checkBinary(const std::string& path, const std::string& data, std::size_t body,
                 const std::vector<Element>& elements, bool bigEndian) {
  std::size_t pos = body;
  const auto left = [&] { return static_cast<std::uint64_t>(data.size() - pos); };
  const auto bytes = [](std::uint64_t n) { return std::to_string(n) + " bytes left in the file"; };
  for (const Element& e : elements) {
    const bool hasList = std::any_of(e.properties.begin(), e.properties.end(),
                                     [](const Property& p) { return p.list; });
    if (e.properties.empty()) {
      checkEmptyElement(path, e, data.size());
      continue;
    }
    if (!hasList) {  // fixed-size entries: checked at once
      std::uint64_t width = 0;
      for (const Property& p : e.properties) width += p.size;
      if (e.count > left() / width) endsEarly(path, left() / width, e);
      pos += e.count * width;
      continue;
    }
    FaceTexcoords texcoords(e);
    for (std::uint64_t i = 0; i < e.count; ++i) {
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (!p.list) {
          if (left() < static_cast<std::uint64_t>(p.size)) endsEarly(path, i, e);
          pos += p.size;
          continue;
        }
        if (left() < static_cast<std::uint64_t>(p.countSize)) endsEarly(path, i, e);
        const std::int64_t length =
            binaryLength(reinterpret_cast<const unsigned char*>(data.data()) + pos, p, bigEndian);
        pos += p.countSize;
        if (length < 0 || static_cast<std::uint64_t>(length) > left() / p.size)
          tooLong(path, p, i, e, std::to_string(length), "the " + bytes(left()) + " hold");
        pos += static_cast<std::size_t>(length) * p.size;
        texcoords.length(k, length);
      }
      texcoords.check(path, i, e);
    }
  }
}

// Reads the file's bytes into data when it is a PLY file: named .ply (any case), or starting
// with "ply". False for another file (an OBJ or STL is not read here: only its first bytes).
bool readPly(const std::string& path, std::string& data) {
  std::ifstream in(path, std::ios::binary);
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (extension != ".ply") {
    char magic[3] = {};
    in.read(magic, sizeof magic);
    if (in.gcount() != sizeof magic || std::string_view(magic, sizeof magic) != "ply") return false;
    in.seekg(0);
  }
  data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return true;
}

// A header is text. assimp 5.2 also ends a line at '\r', '\f' and '\0', and does not take '\v'
// for a blank, so a header with those would be read as other lines than this check reads (a
// fuzz input hid "element 4294967295face 06" behind a '\f'): refused. Bytes from 0x80 up (UTF-8
// in a comment) are left alone.
void refuseControlCharacters(const std::string& path, int n, const std::string& line) {
  const auto control = std::find_if(line.begin(), line.end(), [](char c) {
    return static_cast<unsigned char>(c) < 0x20 && c != '\t';
  });
  if (control == line.end()) return;
  char byte[8];
  std::snprintf(byte, sizeof byte, "0x%02x", static_cast<unsigned char>(*control));
  throw InputError(sourceLocation(path, n, static_cast<int>(control - line.begin()) + 1),
                   std::string("PLY header line holds the control character ") + byte +
                       "; a PLY header is text");
}

// What the header has declared so far.
struct Header {
  std::vector<Element> elements;
  Format format = Format::kUnknown;
  int vertexLists = 0, faceLists = 0;  // the line of the first of each; 0: none yet
};

// "format NAME VERSION": one of the three formats, once. assimp 5.2 goes on with "format
// binary_little_end_header" and allocates for its vertex count until memory runs out (a fuzz
// input).
void readFormat(const std::string& where, const std::string& line, std::istringstream& words,
                Header& header) {
  std::string name;
  words >> name;
  if (header.format != Format::kUnknown)
    throw InputError(where, "PLY header has a second 'format' line");
  header.format = name == "ascii"                  ? Format::kAscii
                  : name == "binary_little_endian" ? Format::kLittleEndian
                  : name == "binary_big_endian"    ? Format::kBigEndian
                                                   : Format::kUnknown;
  if (header.format == Format::kUnknown)
    throw InputError(where, "PLY header line '" + printable(line) +
                                "' should be 'format ascii 1.0', 'format binary_little_endian "
                                "1.0' or 'format binary_big_endian 1.0'");
}

// "element NAME COUNT" on line n. One vertex list and one face list ("face" or "tristrips") at
// most: assimp 5.2 sizes the mesh's arrays by the first such element and writes the next one's
// entries past their end (names matched as assimp matches them: whole words, case-sensitive).
void readElement(const std::string& path, int n, const std::string& line, std::istringstream& words,
                 Header& header) {
  Element e;
  std::string count;
  words >> e.name >> count;
  // COUNT a whole number. assimp 5.2 reads a count from the leading digits of whatever follows
  // the name (none: 0), and reads a name that starts with a digit as the count itself:
  // "element 30000000face 1" took 700 MB and over two minutes (a fuzz input's name of 26 nines,
  // an allocation of 92 GB). Refused, so that the data check follows the file as assimp will.
  const auto [end, error] = std::from_chars(count.data(), count.data() + count.size(), e.count);
  if (error != std::errc() || end != count.data() + count.size() || e.name.empty() ||
      std::isdigit(static_cast<unsigned char>(e.name[0])) != 0)
    throw InputError(sourceLocation(path, n),
                     "PLY header line '" + printable(line) +
                         "' should be 'element NAME COUNT', a name that does not start "
                         "with a digit and a whole number");
  int* first = e.name == "vertex"                          ? &header.vertexLists
               : e.name == "face" || e.name == "tristrips" ? &header.faceLists
                                                           : nullptr;
  if (first != nullptr && *first != 0)
    throw InputError(
        sourceLocation(path, n),
        std::string("PLY header declares a second ") +
            (first == &header.vertexLists ? "vertex list ('element vertex')"
                                          : "face list ('element face' or 'element tristrips')") +
            " (the first is on line " + std::to_string(*first) + "); a mesh has one");
  if (first != nullptr) *first = n;
  header.elements.push_back(std::move(e));
}

// "property TYPE NAME" or "property list LENGTH_TYPE TYPE NAME", after an element line, with
// types PLY has: assimp 5.2 lets a property of another type through and then allocates an
// element's count without the data to hold it (a binary file of 250 bytes declaring 300
// million vertices, one with a property of type "foo": 3.5 GB, 25 s).
void readProperty(const std::string& where, const std::string& line, std::istringstream& words,
                  Header& header) {
  const auto refuse = [&](const std::string& why) {
    throw InputError(where, "PLY header line '" + printable(line) + "' " + why);
  };
  if (header.elements.empty()) refuse("comes before any 'element' line");
  std::string type;
  words >> type;
  Property p;
  if (type == "list") {
    std::string countType;
    words >> countType >> type;
    const Type length = typeNamed(countType);
    if (!length.isInteger)
      refuse("gives a list a length of type '" + printable(countType) +
             "': it should be one of PLY's integer types");
    p.list = true;
    p.countSize = length.size;
    p.countSigned = length.isSigned;
  }
  p.size = typeNamed(type).size;
  if (p.size == 0)
    refuse("has type '" + printable(type) + "': it should be one of PLY's types (" + typeNames() +
           ")");
  words >> p.name;
  header.elements.back().properties.push_back(std::move(p));
}

// At "end_header" on line n, whose newline is at pos: the data against the header.
void checkData(const std::string& path, const std::string& data, std::size_t pos, int n,
               const Header& header) {
  if (header.format == Format::kUnknown)
    throw InputError(sourceLocation(path, n),
                     "PLY header ends without a 'format' line (ascii, binary_little_endian "
                     "or binary_big_endian)");
  if (header.format == Format::kAscii) {
    checkAscii(path, data, pos + 1, n + 1, header.elements);
  } else {
    checkBinary(path, data, pos + 1, header.elements, header.format == Format::kBigEndian);
  }
}

}  // namespace

void checkPlyLayout(const std::string& path) {
  std::string data;
  if (!readPly(path, data)) return;

  // The header, line by line. Lines this check does not know (comment, obj_info, anything
  // else) are left to assimp.
  Header header;
  constexpr int kMaxHeaderLines = 100000;
  std::size_t pos = data.find('\n');  // past the magic number (line 1)
  for (int n = 2; pos != std::string::npos && n <= kMaxHeaderLines; ++n) {
    const std::size_t start = pos + 1;
    pos = data.find('\n', start);
    std::string line =
        data.substr(start, pos == std::string::npos ? std::string::npos : pos - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    // The header's lines each end in a newline, the last one too. assimp 5.2 loops forever on
    // a header cut off inside a property line, and on one cut off after "end_header" when it
    // also holds a line assimp does not know.
    if (pos == std::string::npos) {
      if (line == "end_header")
        throw InputError(sourceLocation(path, n),
                         "PLY file ends inside its 'end_header' line: no newline and no data "
                         "after it (is the file cut off?)");
      break;  // no end_header
    }
    refuseControlCharacters(path, n, line);
    if (line == "end_header") {
      checkData(path, data, pos, n, header);
      return;
    }
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") readFormat(sourceLocation(path, n), line, words, header);
    if (keyword == "element") readElement(path, n, line, words, header);
    if (keyword == "property") readProperty(sourceLocation(path, n), line, words, header);
  }
  throw InputError(path, "PLY header has no 'end_header' line (is the file cut off?)");
}

}  // namespace vf
