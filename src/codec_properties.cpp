// The properties section (format 3.14; format-spec/qsp_format.md, "Properties section"): PLY vertex and
// face properties and the OBJ vertex weight, each value exactly, per output vertex and face. Integers
// as varints of their difference from the previous value, floats as their binary32 or binary64 bits:
// such properties are rare and small beside the mesh, and these are the bits a PLY file holds.
#include <bit>
#include <cmath>
#include <string>
#include <unordered_set>
#include <vector>

#include "bytes.h"
#include "codec_sections.h"
#include "qsp/error.h"

namespace qsp {
namespace {

constexpr std::uint8_t kFaceBit = 0x01, kListBit = 0x02, kBinary64Bit = 0x04, kReservedFlags = 0xF8;
constexpr const char* kSection = "properties section";
// The format's limit on properties: far beyond any PLY file's few, and it bounds what a section of many
// tiny properties costs beside its bytes (each property is an object and a name).
constexpr std::uint64_t kMaxProperties = 65536;

// The integer types' ranges, in ScalarType order.
constexpr std::int64_t kLow[] = {-128, 0, -32768, 0, -2147483648LL, 0};
constexpr std::int64_t kHigh[] = {127, 255, 32767, 65535, 2147483647LL, 4294967295LL};

bool is_float(ScalarType t) { return t == ScalarType::kFloat32 || t == ScalarType::kFloat64; }

// A name a PLY header can hold as one word: printable ASCII without spaces; "" only for the OBJ weight.
bool valid_name(std::string_view name) {
  for (const char c : name)
    if (c <= ' ' || c > '~') return false;
  return true;
}

std::uint64_t zigzag(std::int64_t v) {
  return (static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63);
}
std::int64_t unzigzag(std::uint64_t u) {
  return static_cast<std::int64_t>(u >> 1) ^ -static_cast<std::int64_t>(u & 1);
}

// What is wrong with a property of `elements` elements ("" if nothing): the rules decoders check.
std::string property_problem(const ValueProperty& p, bool face, std::size_t elements) {
  const auto type = static_cast<unsigned>(p.type), count_type = static_cast<unsigned>(p.count_type);
  if (type > static_cast<unsigned>(ScalarType::kFloat64)) return "has an unknown value type";
  if (!valid_name(p.name)) return "has a name a PLY header cannot hold";
  if (p.name.empty() && (face || p.list || !is_float(p.type)))
    return "has no name but is not a vertex weight (a scalar float per vertex)";
  if (p.float64 && !is_float(p.type)) return "is an integer type marked binary64";
  if (p.list &&
      (count_type > static_cast<unsigned>(ScalarType::kUint32) || p.offsets.size() != elements + 1 ||
       p.offsets.front() != 0 || p.offsets.back() != p.values.size()))
    return "has list offsets that disagree with its elements and values";
  if (!p.list && (p.values.size() != elements || !p.offsets.empty()))
    return "does not have one value per element";
  for (std::size_t e = 0; p.list && e < elements; ++e) {
    const std::uint32_t n = p.offsets[e + 1] - p.offsets[e];
    if (p.offsets[e + 1] < p.offsets[e] || n > kHigh[count_type])
      return "has a list longer than its count type holds";
  }
  for (const double v : p.values) {
    if (!is_float(p.type) && (v != std::floor(v) || v < kLow[type] || v > kHigh[type]))
      return "has a value its integer type cannot hold";
    if (is_float(p.type) && !p.float64 && !std::isnan(v) && static_cast<double>(static_cast<float>(v)) != v)
      return "has a value binary32 does not hold but is not marked binary64";
  }
  return "";
}

// The names an element's properties have taken so far: a PLY element cannot hold two of one name. A set,
// not a scan of the earlier properties: a hostile section of a million tiny properties stays linear.
using Names = std::unordered_set<std::string>;

void put_properties(std::string& out, const std::vector<ValueProperty>& props, bool face,
                    std::size_t elements) {
  Names names;
  for (std::size_t i = 0; i < props.size(); ++i) {
    const ValueProperty& p = props[i];
    if (!names.insert(p.name).second)
      throw Error(ErrorCode::kUsage, "encode: two properties of one element named '" + p.name + "'");
    if (const std::string why = property_problem(p, face, elements); !why.empty())
      throw Error(ErrorCode::kUsage, std::string("encode: ") + (face ? "face" : "vertex") + " property " +
                                         std::to_string(i) + " ('" + p.name + "') " + why);
    put_u8(out, static_cast<std::uint8_t>((face ? kFaceBit : 0) | (p.list ? kListBit : 0) |
                                          (p.float64 ? kBinary64Bit : 0)));
    put_u8(out, static_cast<std::uint8_t>(static_cast<unsigned>(p.type) |
                                          (p.list ? static_cast<unsigned>(p.count_type) << 4 : 0u)));
    put_varint(out, p.name.size());
    out += p.name;
    for (std::size_t e = 0; p.list && e < elements; ++e) put_varint(out, p.offsets[e + 1] - p.offsets[e]);
    std::int64_t previous = 0;
    for (const double v : p.values) {
      if (!is_float(p.type)) {
        const auto n = static_cast<std::int64_t>(v);
        put_varint(out, zigzag(n - previous));
        previous = n;
      } else if (p.float64) {
        put_le(out, std::bit_cast<std::uint64_t>(v), 8);
      } else {
        put_le(out, std::bit_cast<std::uint32_t>(static_cast<float>(v)), 4);
      }
    }
  }
}

}  // namespace

std::string encode_properties_section(const std::vector<ValueProperty>& vertex,
                                      const std::vector<ValueProperty>& face, std::size_t vertices,
                                      std::size_t faces) {
  std::size_t weights = 0;
  for (const ValueProperty& p : vertex) weights += p.name.empty();
  if (weights > 1) throw Error(ErrorCode::kUsage, "encode: more than one vertex weight property");
  if (vertex.size() + face.size() > kMaxProperties)
    throw Error(ErrorCode::kUsage, "encode: more than " + std::to_string(kMaxProperties) + " properties");
  std::string out;
  put_varint(out, vertex.size() + face.size());
  put_properties(out, vertex, false, vertices);
  put_properties(out, face, true, faces);
  return out;
}

DecodedProperties decode_properties_section(std::string_view payload, std::uint64_t offset,
                                            std::uint64_t vertices, std::uint64_t faces) {
  ByteReader r(payload, offset, kSection);
  const std::uint64_t count = r.varint("property count");
  // Every property takes at least 3 bytes (flags, types, name length): no allocation a file cannot back.
  if (count == 0 || count > r.left() / 3 || count > kMaxProperties)
    r.fail("property count " + std::to_string(count) + " does not fit the section or the limit of " +
           std::to_string(kMaxProperties));
  DecodedProperties out;
  bool face_seen = false, weight_seen = false;
  Names vertex_names, face_names;
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::uint64_t at = r.offset();
    const std::uint8_t flags = r.u8("property flags");
    const std::uint8_t types = r.u8("property types");
    const auto fail = [&](const std::string& why) {
      r.fail_at("property " + std::to_string(i) + " " + why, at);
    };
    if (flags & kReservedFlags) fail("has reserved flag bits set");
    const bool face = flags & kFaceBit;
    if (face_seen && !face) fail("is a vertex property after a face property");
    face_seen = face;
    ValueProperty p;
    p.list = flags & kListBit;
    p.float64 = flags & kBinary64Bit;
    if ((types & 0x0F) > static_cast<unsigned>(ScalarType::kFloat64) ||
        (p.list ? (types >> 4) > static_cast<unsigned>(ScalarType::kUint32) : (types >> 4) != 0))
      fail("has an invalid type byte");
    p.type = static_cast<ScalarType>(types & 0x0F);
    p.count_type = p.list ? static_cast<ScalarType>(types >> 4) : ScalarType::kUint8;
    p.name = std::string(r.take(r.varint("name length"), "name"));
    const std::uint64_t elements = face ? faces : vertices;
    if (p.name.empty() && !face && !p.list && is_float(p.type)) {
      if (weight_seen) fail("is a second vertex weight property");
      weight_seen = true;
    }
    std::uint64_t values = elements;
    if (p.list) {
      if (elements > r.left())
        fail("has " + std::to_string(elements) + " list lengths but the section has " +
             std::to_string(r.left()) + " bytes left");
      p.offsets.assign(elements + 1, 0);
      values = 0;
      for (std::uint64_t e = 0; e < elements; ++e) {
        const std::uint64_t n = r.varint("list length");
        if (n > static_cast<std::uint64_t>(kHigh[static_cast<unsigned>(p.count_type)]) ||
            values + n > 0xFFFFFFFFu)
          fail("has a list length its count type or the format cannot hold");
        values += n;
        p.offsets[e + 1] = static_cast<std::uint32_t>(values);
      }
    }
    const std::uint64_t width = !is_float(p.type) ? 1 : p.float64 ? 8 : 4;  // bytes a value takes at least
    if (values > r.left() / width)
      fail("has " + std::to_string(values) + " values but the section has " + std::to_string(r.left()) +
           " bytes left");
    p.values.resize(values);
    std::int64_t previous = 0;
    for (double& v : p.values) {
      if (!is_float(p.type)) {
        const std::uint64_t u = r.varint("value");
        // Two values of a 32-bit type differ by less than 2^33: anything more is refused before adding.
        const std::int64_t n = u >> 34 ? kHigh[5] + 1 : previous + unzigzag(u);
        if (n < kLow[static_cast<unsigned>(p.type)] || n > kHigh[static_cast<unsigned>(p.type)])
          fail("has a value its integer type cannot hold");
        v = static_cast<double>(n);
        previous = n;
      } else if (p.float64) {
        v = std::bit_cast<double>(r.le(8, "value"));
      } else {
        v = std::bit_cast<float>(static_cast<std::uint32_t>(r.le(4, "value")));
      }
    }
    if (const std::string why = property_problem(p, face, elements); !why.empty()) fail(why);
    if (!(face ? face_names : vertex_names).insert(p.name).second)
      fail("has the name of an earlier property of its element");
    (face ? out.face : out.vertex).push_back(std::move(p));
  }
  if (r.left()) r.fail("bytes after the last property");
  return out;
}

}  // namespace qsp
