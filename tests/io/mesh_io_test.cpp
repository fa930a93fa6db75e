// OBJ and PLY loaders: expected triangles, and malformed files rejected with file (and line) named.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "io/mesh_io.h"

namespace fs = std::filesystem;
using namespace vpm;

namespace {

using Tri = std::array<uint32_t, 3>;

// One folder for the whole test binary, removed when it exits.
const fs::path& temp_dir() {
    static const struct Folder {
        fs::path path = fs::temp_directory_path() / ("vpm_mesh_io_" + std::to_string(::getpid()));
        Folder() { fs::create_directories(path); }
        ~Folder() {
            std::error_code ec;
            fs::remove_all(path, ec);
        }
    } folder;
    return folder.path;
}

std::string write_file(const std::string& name, const std::string& bytes) {
    const fs::path p = temp_dir() / name;
    std::ofstream out(p, std::ios::binary);
    out << bytes;
    return p.string();
}

// FileError whose message contains every one of `parts`.
template <class F>
void expect_file_error(F f, const std::vector<std::string>& parts) {
    try {
        f();
        ADD_FAILURE() << "no FileError thrown";
    } catch (const FileError& e) {
        for (const auto& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what() << " lacks " << p;
    }
}

template <class T>
void put(std::string& s, T v, bool big_endian = false) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));
    s.append(b, sizeof(T));
}

}  // namespace

TEST(ObjLoader, FansNegativeIndicesAndSlashForms) {
    const std::string path = write_file("forms.obj",
        "# comment\nmtllib x.mtl\no thing\ng group\ns 1\nusemtl red\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvt 0 0\nvn 0 0 1\n"
        "f 1/1/1 2/1/1 3/1/1 4/1/1\n"   // quad -> two triangles
        "f -4//1 -3//1 -1//1  # trailing comment\n"
        "f 2/1 3/1 4/1\r\n");
    const TriangleMesh m = load_obj(path);
    ASSERT_EQ(m.vertices.size(), 4u);
    EXPECT_EQ(m.vertices[2], Vec3(1, 1, 0));
    ASSERT_EQ(m.triangles.size(), 4u);
    EXPECT_EQ(m.triangles[0], (Tri{0, 1, 2}));
    EXPECT_EQ(m.triangles[1], (Tri{0, 2, 3}));
    EXPECT_EQ(m.triangles[2], (Tri{0, 1, 3}));
    EXPECT_EQ(m.triangles[3], (Tri{1, 2, 3}));
}

TEST(ObjLoader, DataFile) {
    const TriangleMesh m = load_mesh(std::string(VPM_TEST_DATA_DIR) + "/tetra.obj");
    EXPECT_EQ(m.vertices.size(), 4u);
    EXPECT_EQ(m.triangles.size(), 4u);
    EXPECT_EQ(m.triangles[3], (Tri{1, 2, 3}));
}

TEST(ObjLoader, MalformedFilesNameFileAndLine) {
    const std::string bad_index = write_file("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n");
    expect_file_error([&] { load_obj(bad_index); }, {"bad_index.obj:5:", "out of range"});
    const std::string zero = write_file("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    expect_file_error([&] { load_obj(zero); }, {"zero.obj:4:", "out of range"});
    const std::string negative = write_file("neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
    expect_file_error([&] { load_obj(negative); }, {"neg.obj:4:", "out of range"});
    const std::string nan = write_file("nonnum.obj", "v 0 0 0\nv 1 abc 0\n");
    expect_file_error([&] { load_obj(nan); }, {"nonnum.obj:2:", "abc"});
    const std::string partial = write_file("partial.obj", "v 0 0 0\nv 1 2.5x 0\n");
    expect_file_error([&] { load_obj(partial); }, {"partial.obj:2:", "2.5x"});
    const std::string inf = write_file("inf.obj", "v 0 0 inf\n");
    expect_file_error([&] { load_obj(inf); }, {"inf.obj:1:"});
    const std::string short_face = write_file("short.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
    expect_file_error([&] { load_obj(short_face); }, {"short.obj:3:", "three"});
    const std::string bad_ref = write_file("badref.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x/2 3\n");
    expect_file_error([&] { load_obj(bad_ref); }, {"badref.obj:4:", "x/2"});
    const std::string unknown = write_file("curv.obj", "v 0 0 0\ncurv 0 1 1 2\n");
    expect_file_error([&] { load_obj(unknown); }, {"curv.obj:2:", "curv"});
    const std::string empty = write_file("empty.obj", "v 0 0 0\n");
    expect_file_error([&] { load_obj(empty); }, {"empty.obj", "no faces"});
    expect_file_error([&] { load_obj((temp_dir() / "missing.obj").string()); }, {"missing.obj", "cannot open"});
}

TEST(PlyLoader, AsciiSkipsOtherPropertiesAndElements) {
    const std::string path = write_file("ascii.ply",
        "ply\nformat ascii 1.0\ncomment made by hand\n"
        "element vertex 4\nproperty float x\nproperty float y\nproperty float nx\nproperty double z\n"
        "property uchar red\nproperty list uchar int extra\n"
        "element face 2\nproperty uchar flags\nproperty list uchar int vertex_indices\nproperty float quality\n"
        "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
        "end_header\n"
        "0 0 9 0 255 2 7 7\n1 0 9 0 255 0\n1 1 9 0.5 255 1 3\n0 1 9 0.5 255 0\n"
        "1 4 0 1 2 3 0.5\n0 3 3 2 1 1.5\n"
        "0 1\n");
    const TriangleMesh m = load_ply(path);
    ASSERT_EQ(m.vertices.size(), 4u);
    EXPECT_EQ(m.vertices[2], Vec3(1, 1, 0.5));
    ASSERT_EQ(m.triangles.size(), 3u);
    EXPECT_EQ(m.triangles[0], (Tri{0, 1, 2}));
    EXPECT_EQ(m.triangles[1], (Tri{0, 2, 3}));
    EXPECT_EQ(m.triangles[2], (Tri{3, 2, 1}));
}

namespace {
// Binary PLY of 4 vertices (double x y z + a float property) and a quad + a triangle.
std::string binary_ply(bool big) {
    std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty float confidence\n"
                    "property double z\nelement face 2\nproperty list uchar uint vertex_indices\n"
                    "property short tag\nend_header\n";
    const double v[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.25}, {0, 1, -3.5}};
    for (const auto& p : v) {
        put<double>(s, p[0], big);
        put<double>(s, p[1], big);
        put<float>(s, 0.5f, big);
        put<double>(s, p[2], big);
    }
    put<uint8_t>(s, 4);
    for (uint32_t i : {0u, 1u, 2u, 3u}) put<uint32_t>(s, i, big);
    put<int16_t>(s, -7, big);
    put<uint8_t>(s, 3);
    for (uint32_t i : {3u, 2u, 1u}) put<uint32_t>(s, i, big);
    put<int16_t>(s, 12, big);
    return s;
}
}  // namespace

TEST(PlyLoader, BinaryLittleAndBigEndian) {
    for (bool big : {false, true}) {
        const TriangleMesh m = load_mesh(write_file(big ? "be.PLY" : "le.ply", binary_ply(big)));
        ASSERT_EQ(m.vertices.size(), 4u);
        EXPECT_EQ(m.vertices[2], Vec3(1, 1, 0.25));
        EXPECT_EQ(m.vertices[3], Vec3(0, 1, -3.5));
        ASSERT_EQ(m.triangles.size(), 3u);
        EXPECT_EQ(m.triangles[0], (Tri{0, 1, 2}));
        EXPECT_EQ(m.triangles[1], (Tri{0, 2, 3}));
        EXPECT_EQ(m.triangles[2], (Tri{3, 2, 1}));
    }
}

TEST(PlyLoader, MalformedFilesNameFile) {
    const std::string full = binary_ply(false);
    for (size_t cut : {size_t(10), size_t(3)}) {   // inside the last face, inside the last tag
        const std::string p = write_file("truncated.ply", full.substr(0, full.size() - cut));
        expect_file_error([&] { load_ply(p); }, {"truncated.ply: ", "truncated"});
    }
    std::string unknown = full;
    unknown.replace(unknown.find("binary_little_endian"), 20, "binary_middle_endian");
    const std::string p2 = write_file("format.ply", unknown);
    expect_file_error([&] { load_ply(p2); }, {"format.ply: ", "unsupported PLY format", "binary_middle_endian"});

    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::string p3 = write_file("range.ply", head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
    expect_file_error([&] { load_ply(p3); }, {"range.ply: ", "vertex index 3 out of range"});
    const std::string p4 = write_file("nonnum.ply", head + "0 0 0\n1 zz 0\n0 1 0\n3 0 1 2\n");
    expect_file_error([&] { load_ply(p4); }, {"nonnum.ply: ", "non-numeric", "zz"});
    const std::string p5 = write_file("short.ply", head + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n");
    expect_file_error([&] { load_ply(p5); }, {"short.ply: ", "end of file"});
    const std::string p6 = write_file("magic.ply", "plx\n" + head.substr(4));
    expect_file_error([&] { load_ply(p6); }, {"magic.ply: ", "not a PLY"});
    const std::string p7 = write_file("noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\n");
    expect_file_error([&] { load_ply(p7); }, {"noend.ply: ", "end_header"});
    const std::string p8 = write_file("nofaces.ply",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n");
    expect_file_error([&] { load_ply(p8); }, {"nofaces.ply: ", "no faces"});
    expect_file_error([&] { load_mesh(write_file("mesh.stl", "solid")); }, {"mesh.stl", "unsupported mesh format"});
}
