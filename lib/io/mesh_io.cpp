#include "io/mesh_io.h"

#include <algorithm>
#include <functional>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "core/error.h"

namespace vpm {
namespace {

std::string read_all(const std::string& path) {
    // An ifstream opens a folder without complaint and reads nothing ("no faces"): say what it is.
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (std::filesystem::is_directory(st)) throw FileError(path + ": cannot read mesh: it is a folder, not a file");
    if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
        throw FileError(path + ": cannot read mesh: not a regular file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(path + ": cannot open mesh file");
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) throw FileError(path + ": read error");
    return s.str();
}

// Whole-token number parse; false when the token is not a number.
bool parse_double(const std::string& tok, double& out) {
    if (tok.empty()) return false;
    char* end = nullptr;
    errno = 0;
    out = std::strtod(tok.c_str(), &end);
    return end == tok.c_str() + tok.size() && errno != ERANGE;
}

bool parse_int(const std::string& tok, long long& out) {
    if (tok.empty()) return false;
    char* end = nullptr;
    errno = 0;
    out = std::strtoll(tok.c_str(), &end, 10);
    return end == tok.c_str() + tok.size() && errno != ERANGE;
}

void fan(const std::vector<uint32_t>& poly, std::vector<std::array<uint32_t, 3>>& tris) {
    for (size_t i = 1; i + 1 < poly.size(); ++i) tris.push_back({poly[0], poly[i], poly[i + 1]});
}

// ---------------------------------------------------------------------------------------------
// PLY

enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

bool ply_type(const std::string& s, PlyType& t) {
    static const std::pair<const char*, PlyType> names[] = {
        {"char", PlyType::i8},    {"int8", PlyType::i8},     {"uchar", PlyType::u8},
        {"uint8", PlyType::u8},   {"short", PlyType::i16},   {"int16", PlyType::i16},
        {"ushort", PlyType::u16}, {"uint16", PlyType::u16},  {"int", PlyType::i32},
        {"int32", PlyType::i32},  {"uint", PlyType::u32},    {"uint32", PlyType::u32},
        {"float", PlyType::f32},  {"float32", PlyType::f32}, {"double", PlyType::f64},
        {"float64", PlyType::f64}};
    for (const auto& [n, v] : names)
        if (s == n) { t = v; return true; }
    return false;
}

size_t ply_size(PlyType t) {
    switch (t) {
        case PlyType::i8: case PlyType::u8: return 1;
        case PlyType::i16: case PlyType::u16: return 2;
        case PlyType::i32: case PlyType::u32: case PlyType::f32: return 4;
        case PlyType::f64: return 8;
    }
    return 0;
}

bool ply_is_integer(PlyType t) { return t != PlyType::f32 && t != PlyType::f64; }

struct PlyProperty {
    std::string name;
    bool is_list = false;
    PlyType count_type = PlyType::u8;
    PlyType type = PlyType::f32;
};

struct PlyElement {
    std::string name;
    size_t count = 0;
    std::vector<PlyProperty> props;
};

// Where a value sits, turned into text only when an error is reported.
struct PlyWhere {
    const std::string& element;
    size_t index;
    const std::string& property;
    const char* suffix = "";
    std::string str() const {
        return "element '" + element + "' " + std::to_string(index) + ", property '" + property + "'" + suffix;
    }
};

// Sequential reader over the body: ascii tokens or binary values of either byte order.
class PlyBody {
public:
    PlyBody(const std::string& file, const std::string& data, size_t pos, int format)
        : file_(file), data_(data), pos_(pos), format_(format) {}

    // Reads one value of type t as a double; `what` names it for error messages.
    double read(PlyType t, const PlyWhere& what) {
        if (format_ == 0) {
            const std::string tok = token();
            if (tok.empty()) throw FileError(file_ + ": unexpected end of file reading " + what.str());
            double v;
            if (!parse_double(tok, v))
                throw FileError(file_ + ": non-numeric value \"" + tok + "\" in " + what.str());
            if (ply_is_integer(t) && v != std::floor(v))
                throw FileError(file_ + ": non-integer value \"" + tok + "\" for an integer property in " + what.str());
            return v;
        }
        const size_t n = ply_size(t);
        if (pos_ + n > data_.size())
            throw FileError(file_ + ": truncated binary data reading " + what.str() + " (file ends at byte " +
                            std::to_string(data_.size()) + ")");
        unsigned char b[8];
        std::memcpy(b, data_.data() + pos_, n);
        pos_ += n;
        if (format_ == 2) std::reverse(b, b + n);   // big-endian file on a little-endian host
        switch (t) {
            case PlyType::i8: { int8_t v; std::memcpy(&v, b, 1); return v; }
            case PlyType::u8: { uint8_t v; std::memcpy(&v, b, 1); return v; }
            case PlyType::i16: { int16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::u16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::i32: { int32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::u32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::f32: { float v; std::memcpy(&v, b, 4); return v; }
            case PlyType::f64: { double v; std::memcpy(&v, b, 8); return v; }
        }
        return 0.0;
    }

private:
    std::string token() {
        while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
        const size_t start = pos_;
        while (pos_ < data_.size() && !std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
        return data_.substr(start, pos_ - start);
    }

    const std::string& file_;
    const std::string& data_;
    size_t pos_;
    int format_;   // 0 ascii, 1 binary little endian, 2 binary big endian
};

}  // namespace

TriangleMesh load_obj(const std::string& path) {
    const std::string text = read_all(path);
    TriangleMesh mesh;
    std::istringstream in(text);
    std::string line;
    size_t line_no = 0;
    std::vector<uint32_t> poly;
    auto fail = [&](const std::string& what) -> void {
        throw FileError(path + ":" + std::to_string(line_no) + ": " + what);
    };
    while (std::getline(in, line)) {
        ++line_no;
        if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        std::istringstream ls(line);
        std::string key;
        if (!(ls >> key)) continue;
        if (key == "v") {
            Vec3 p;
            for (int c = 0; c < 3; ++c) {
                std::string tok;
                if (!(ls >> tok)) fail("vertex needs three coordinates");
                if (!parse_double(tok, p[c]) || !std::isfinite(p[c]))
                    fail("non-numeric or non-finite coordinate \"" + tok + "\"");
            }
            mesh.vertices.push_back(p);
        } else if (key == "f") {
            poly.clear();
            std::string tok;
            while (ls >> tok) {
                const std::string first = tok.substr(0, tok.find('/'));
                long long i;
                if (!parse_int(first, i)) fail("bad vertex reference \"" + tok + "\"");
                const long long n = static_cast<long long>(mesh.vertices.size());
                const long long idx = i > 0 ? i - 1 : n + i;
                if (i == 0 || idx < 0 || idx >= n)
                    fail("vertex index " + std::to_string(i) + " out of range (" + std::to_string(n) +
                         " vertices defined so far)");
                poly.push_back(static_cast<uint32_t>(idx));
            }
            if (poly.size() < 3) fail("face needs at least three vertices");
            fan(poly, mesh.triangles);
        } else if (key == "vt" || key == "vn" || key == "vp" || key == "usemtl" || key == "mtllib" ||
                   key == "o" || key == "g" || key == "s" || key == "l" || key == "p") {
            continue;
        } else {
            fail("unsupported OBJ statement \"" + key + "\"");
        }
    }
    if (mesh.triangles.empty()) throw FileError(path + ": OBJ file contains no faces");
    return mesh;
}

namespace {

// A PLY header: its format (0 ascii, 1 binary little endian, 2 binary big endian), its elements and
// where the body starts.
struct PlyHeader {
    int format = -1;
    std::vector<PlyElement> elements;
    size_t body = 0;
};

PlyHeader read_ply_header(const std::string& path, const std::string& data) {
    auto fail = [&](const std::string& what) -> void { throw FileError(path + ": " + what); };
    PlyHeader h;
    size_t pos = 0;
    auto next_line = [&](std::string& out) {
        if (pos >= data.size()) return false;
        size_t end = data.find('\n', pos);
        if (end == std::string::npos) end = data.size();
        out = data.substr(pos, end - pos);
        if (!out.empty() && out.back() == '\r') out.pop_back();
        pos = std::min(end + 1, data.size());
        return true;
    };
    std::string line;
    if (!next_line(line) || line != "ply") fail("not a PLY file (missing \"ply\" magic line)");
    int& format = h.format;
    std::vector<PlyElement>& elements = h.elements;
    bool ended = false;
    while (next_line(line)) {
        std::istringstream ls(line);
        std::string key;
        if (!(ls >> key)) continue;
        if (key == "comment" || key == "obj_info") continue;
        if (key == "format") {
            std::string f, version;
            ls >> f >> version;
            if (f == "ascii") format = 0;
            else if (f == "binary_little_endian") format = 1;
            else if (f == "binary_big_endian") format = 2;
            else fail("unsupported PLY format \"" + f + "\" (ascii, binary_little_endian, binary_big_endian)");
            if (version != "1.0") fail("unsupported PLY version \"" + version + "\" (1.0)");
        } else if (key == "element") {
            PlyElement e;
            std::string count;
            long long c;
            if (!(ls >> e.name >> count) || !parse_int(count, c) || c < 0) fail("bad element line \"" + line + "\"");
            e.count = static_cast<size_t>(c);
            elements.push_back(e);
        } else if (key == "property") {
            if (elements.empty()) fail("property before any element");
            PlyProperty p;
            std::string t;
            ls >> t;
            if (t == "list") {
                std::string ct, it;
                ls >> ct >> it >> p.name;
                p.is_list = true;
                if (!ply_type(ct, p.count_type) || !ply_is_integer(p.count_type) || !ply_type(it, p.type))
                    fail("bad list property \"" + line + "\"");
            } else {
                ls >> p.name;
                if (!ply_type(t, p.type)) fail("unknown property type \"" + t + "\"");
            }
            if (p.name.empty()) fail("property without a name: \"" + line + "\"");
            elements.back().props.push_back(p);
        } else if (key == "end_header") {
            ended = true;
            break;
        } else {
            fail("unknown header line \"" + line + "\"");
        }
    }
    if (!ended) fail("header has no end_header");
    if (format < 0) fail("header has no format line");
    h.body = pos;
    return h;
}

// Where an element's properties are: the vertex coordinates' and the face index list's indices (-1: none).
struct PlyLayout {
    int xyz[3] = {-1, -1, -1};
    int indices = -1;
};

PlyLayout ply_layout(const PlyElement& e, const std::function<void(const std::string&)>& fail) {
    PlyLayout l;
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    for (size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        if (is_vertex && !p.is_list) {
            if (p.name == "x") l.xyz[0] = static_cast<int>(k);
            if (p.name == "y") l.xyz[1] = static_cast<int>(k);
            if (p.name == "z") l.xyz[2] = static_cast<int>(k);
        }
        if (is_face && p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) {
            if (!ply_is_integer(p.type)) fail("face indices must be integers");
            l.indices = static_cast<int>(k);
        }
    }
    return l;
}

}  // namespace

TriangleMesh load_ply(const std::string& path) {
    const std::string data = read_all(path);
    auto fail = [&](const std::string& what) -> void { throw FileError(path + ": " + what); };
    const PlyHeader header = read_ply_header(path, data);
    TriangleMesh mesh;
    PlyBody body(path, data, header.body, header.format);
    bool have_vertex = false, have_face = false;
    std::vector<uint32_t> poly;
    for (const PlyElement& e : header.elements) {
        const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
        const PlyLayout layout = ply_layout(e, fail);
        const int* xyz = layout.xyz;
        const int indices = layout.indices;
        if (is_vertex) {
            if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) fail("vertex element lacks x, y or z");
            have_vertex = true;
            mesh.vertices.reserve(std::min(e.count, data.size()));   // a corrupt count must not allocate
        }
        if (is_face) {
            if (indices < 0) fail("face element lacks a vertex_indices list");
            have_face = true;
        }
        for (size_t i = 0; i < e.count; ++i) {
            Vec3 v = Vec3::Zero();
            for (size_t k = 0; k < e.props.size(); ++k) {
                const PlyProperty& p = e.props[k];
                const PlyWhere what{e.name, i, p.name};
                if (!p.is_list) {
                    const double x = body.read(p.type, what);
                    for (int c = 0; c < 3; ++c)
                        if (is_vertex && xyz[c] == static_cast<int>(k)) {
                            if (!std::isfinite(x)) fail("non-finite coordinate in " + what.str());
                            v[c] = x;
                        }
                    continue;
                }
                const double n = body.read(p.count_type, PlyWhere{e.name, i, p.name, " (list count)"});
                if (n < 0) fail("negative list count in " + what.str());
                const bool keep = is_face && indices == static_cast<int>(k);
                if (keep) poly.clear();
                for (size_t j = 0; j < static_cast<size_t>(n); ++j) {
                    const double idx = body.read(p.type, what);
                    if (!keep) continue;
                    if (idx < 0 || idx >= static_cast<double>(mesh.vertices.size()))
                        fail("vertex index " + std::to_string(static_cast<long long>(idx)) + " out of range in " +
                             what.str() + " (" + std::to_string(mesh.vertices.size()) + " vertices)");
                    poly.push_back(static_cast<uint32_t>(idx));
                }
                if (keep) {
                    if (poly.size() < 3) fail("face with fewer than three vertices in " + what.str());
                    fan(poly, mesh.triangles);
                }
            }
            if (is_vertex) mesh.vertices.push_back(v);
        }
        if (is_face && !have_vertex) fail("face element before the vertex element");
    }
    if (!have_vertex) fail("no vertex element");
    if (!have_face || mesh.triangles.empty()) fail("PLY file contains no faces");
    return mesh;
}

TriangleMesh load_mesh(const std::string& path) {
    std::string ext;
    if (const size_t dot = path.find_last_of('.'); dot != std::string::npos) ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext == "obj") return load_obj(path);
    if (ext == "ply") return load_ply(path);
    throw FileError(path + ": unsupported mesh format \"." + ext + "\" (.obj or .ply)");
}

}  // namespace vpm
