// MATLAB level-5 MAT-file structure (MathWorks, "MAT-File Format", 2021, chapter 1): a 128-byte
// header, then data elements, each an 8-byte tag (type, byte count; or a "small data element"
// packing both and up to 4 bytes of data into the tag), padded to 8 bytes.
#include "mat_structure.hpp"

#include <brdfbake/core/memory_budget.hpp>

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "measured_common.hpp"

namespace brdfbake::measured {
namespace {

enum : std::uint32_t {
  miINT8 = 1,
  miUINT8 = 2,
  miINT16 = 3,
  miUINT16 = 4,
  miINT32 = 5,
  miUINT32 = 6,
  miSINGLE = 7,
  miDOUBLE = 9,
  miINT64 = 12,
  miUINT64 = 13,
  miMATRIX = 14,
  miCOMPRESSED = 15,
  miUTF8 = 16,
  miUTF16 = 17,
  miUTF32 = 18,
};
enum : std::uint32_t { mxCELL = 1, mxSTRUCT = 2, mxOBJECT = 3, mxCHAR = 4, mxSPARSE = 5, mxFUNCTION = 16 };

std::size_t valueSize(std::uint32_t type) {
  switch (type) {
    case miINT8:
    case miUINT8:
    case miUTF8:
      return 1;
    case miINT16:
    case miUINT16:
    case miUTF16:
      return 2;
    case miINT32:
    case miUINT32:
    case miSINGLE:
    case miUTF32:
      return 4;
    case miDOUBLE:
    case miINT64:
    case miUINT64:
      return 8;
    default:
      return 0;
  }
}

// One data element: its type, and where its data lies in the buffer being walked.
struct Element {
  std::uint32_t type = 0;
  std::size_t begin = 0, size = 0;  // the data
  std::size_t next = 0;             // the next element (after padding)
};

class Walker {
 public:
  Walker(const std::string& file, bool swapped) : file_(file), swapped_(swapped) {}

  // Walks the elements of bytes[begin, end) (the file's top level, or an inflated element).
  void walkSequence(std::string_view bytes, std::size_t begin, std::size_t end, int depth) {
    for (std::size_t at = begin; at < end;) {
      const Element e = element(bytes, at, end, "a data element");
      if (e.type == miCOMPRESSED) {
        if (depth > 0) fail("a compressed element inside a compressed element");
        const std::string inflated = inflate(bytes.substr(e.begin, e.size));
        walkSequence(inflated, 0, inflated.size(), depth + 1);
      } else if (e.type == miMATRIX) {
        walkArray(bytes, e, 0);
      }
      at = e.next;
    }
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { throw malformed(file_, 0, message); }

  std::uint32_t word(std::string_view bytes, std::size_t at) const {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    return swapped_ ? __builtin_bswap32(v) : v;
  }

  // The element whose tag is at `at`, which must lie with its data before `end`.
  Element element(std::string_view bytes, std::size_t at, std::size_t end, const char* what) const {
    if (end - at < 8) fail(std::string("truncated: ") + what + " at byte " + std::to_string(at) + " has no whole tag");
    const std::uint32_t first = word(bytes, at);
    Element e;
    if ((first >> 16) != 0) {  // small data element: count in the upper half, data in the next 4 bytes
      e.type = first & 0xFFFFu;
      e.size = first >> 16;
      if (e.size > 4)
        fail(std::string(what) + " at byte " + std::to_string(at) + ": a small element of more than 4 bytes");
      e.begin = at + 4;
      e.next = at + 8;
      return e;
    }
    e.type = first;
    e.size = word(bytes, at + 4);
    e.begin = at + 8;
    if (e.size > end - e.begin) {
      fail(std::string("truncated: ") + what + " at byte " + std::to_string(at) + " claims " + std::to_string(e.size) +
           " bytes, but only " + std::to_string(end - e.begin) + " follow within its parent");
    }
    const std::size_t padded = e.type == miCOMPRESSED ? e.size : (e.size + 7) / 8 * 8;
    e.next = std::min(end, e.begin + padded);
    return e;
  }

  // An array (miMATRIX): flags, dimensions, name, then what its class holds.
  void walkArray(std::string_view bytes, const Element& array, int nesting) {
    if (nesting > kMaxMatNesting) fail("cells or structs nested more than " + std::to_string(kMaxMatNesting) + " deep");
    if (array.size == 0) return;  // an empty array (an empty cell)
    const std::size_t end = array.begin + array.size;
    const Element flags = element(bytes, array.begin, end, "an array's flags");
    if (flags.size < 8) fail("an array's flags at byte " + std::to_string(array.begin) + " are shorter than 8 bytes");
    const std::uint32_t arrayClass = word(bytes, flags.begin) & 0xFFu;
    const bool complex = (word(bytes, flags.begin) & 0x800u) != 0;
    const Element dims = element(bytes, flags.next, end, "an array's dimensions");
    if (dims.type != miINT32 || dims.size % 4 != 0 || dims.size > 32 * 4) fail("an array's dimensions are malformed");
    double count = 1.0;
    for (std::size_t i = 0; i < dims.size; i += 4) {
      const auto d = static_cast<std::int32_t>(word(bytes, dims.begin + i));
      if (d < 0) fail("an array has a negative dimension");
      count *= d;
    }
    const Element name = element(bytes, dims.next, end, "an array's name");
    const std::size_t rest = name.next;
    const double room = static_cast<double>(end - std::min(rest, end));
    if (arrayClass == mxCELL) {
      if (count > room / 8.0) fail(tooMany(count, "cells", end - array.begin));
      std::size_t at = rest;
      for (double i = 0; i < count; ++i) {
        const Element cell = element(bytes, at, end, "a cell");
        if (cell.type != miMATRIX) fail("a cell is not an array");
        walkArray(bytes, cell, nesting + 1);
        at = cell.next;
      }
    } else if (arrayClass == mxSTRUCT || arrayClass == mxOBJECT) {
      walkStruct(bytes, rest, end, count, arrayClass == mxOBJECT, nesting);
    } else if (arrayClass != mxSPARSE && arrayClass != mxFUNCTION && arrayClass <= 15) {
      requireValues(bytes, rest, end, count, "real part");
      if (complex) requireValues(bytes, element(bytes, rest, end, "a real part").next, end, count, "imaginary part");
    }
  }

  // A numeric, logical or char array's data element at `at` holds `count` values at least.
  void requireValues(std::string_view bytes, std::size_t at, std::size_t end, double count, const char* what) const {
    if (count == 0) return;
    const Element data = element(bytes, at, end, what);
    const std::size_t size = valueSize(data.type);
    if (size == 0) fail(std::string("an array's ") + what + " has data of unknown type " + std::to_string(data.type));
    if (count > static_cast<double>(data.size / size)) {
      fail("an array claims " + std::to_string(static_cast<long long>(count)) + " values, but its " + what + " holds " +
           std::to_string(data.size / size));
    }
  }

  void walkStruct(std::string_view bytes, std::size_t at, std::size_t end, double count, bool object, int nesting) {
    if (object) at = element(bytes, at, end, "an object's class name").next;
    const Element length = element(bytes, at, end, "a struct's field name length");
    if (length.size != 4) fail("a struct's field name length is malformed");
    const std::uint32_t nameLength = word(bytes, length.begin);
    const Element names = element(bytes, length.next, end, "a struct's field names");
    if (nameLength == 0 || nameLength > 4096) fail("a struct's field name length is not valid");
    const double fields = static_cast<double>(names.size / nameLength);
    const double room = static_cast<double>(end - std::min(names.next, end));
    if (count * fields > room / 8.0) fail(tooMany(count * fields, "struct fields", end - at));
    std::size_t next = names.next;
    for (double i = 0; i < count * fields; ++i) {
      const Element field = element(bytes, next, end, "a struct field");
      if (field.type != miMATRIX) fail("a struct field is not an array");
      walkArray(bytes, field, nesting + 1);
      next = field.next;
    }
  }

  std::string tooMany(double count, const char* what, std::size_t bytes) const {
    return "an array claims " + std::to_string(static_cast<long long>(std::min(count, 9e18))) + " " + what +
           ", more than its " + std::to_string(bytes) + " bytes can hold (8 bytes each at least)";
  }

  // zlib data inflated, at most 1032 bytes per byte (deflate's limit) and within the memory budget.
  std::string inflate(std::string_view compressed) const {
    const double limit = std::min(1032.0 * static_cast<double>(compressed.size()) + 1024.0,
                                  static_cast<double>(memoryBudgetBytes()) / 2);
    std::string out;
    z_stream stream{};
    if (inflateInit(&stream) != Z_OK) fail("zlib cannot start");
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
    stream.avail_in = static_cast<uInt>(compressed.size());
    int status = Z_OK;
    while (status == Z_OK) {
      if (static_cast<double>(out.size()) >= limit) break;
      out.resize(out.size() + 65536);
      stream.next_out = reinterpret_cast<Bytef*>(out.data() + out.size() - 65536);
      stream.avail_out = 65536;
      status = ::inflate(&stream, Z_NO_FLUSH);
      out.resize(out.size() - stream.avail_out);
    }
    inflateEnd(&stream);
    if (status == Z_OK) fail("a compressed variable inflates to more than " + std::to_string(out.size()) + " bytes");
    if (status != Z_STREAM_END) fail("a compressed variable does not inflate (corrupt or truncated)");
    return out;
  }

  const std::string& file_;
  bool swapped_;
};

}  // namespace

void requireSaneMatStructure(std::string_view bytes, const std::string& file) {
  if (bytes.size() < 128) throw malformed(file, 0, "truncated: shorter than the 128-byte header");
  const bool swapped = bytes[126] == 'M' && bytes[127] == 'I';  // the file's byte order differs from ours
  Walker(file, swapped).walkSequence(bytes, 128, bytes.size(), 0);
}

}  // namespace brdfbake::measured
