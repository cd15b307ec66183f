// The files of `spall surface`: the reader of Spall's own VTU/PVTU/PVD output must give back
// exactly what write_vtu, write_pvtu and PvdSeries wrote, and refuse other files with the path and
// the reason; the VTP and PLY writers must produce files whose counts and bytes add up. (VTK's own
// reader opens a real .vtp in tests/scripts/test_cli_surface.sh, a .pvtu in test_mpi_*.sh.)
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "spall/core/error.hpp"
#include "spall/io/input/vtu_read.hpp"
#include "spall/io/output/ply.hpp"
#include "spall/io/output/vtp.hpp"
#include "spall/io/output/vtu.hpp"

namespace {

namespace fs = std::filesystem;
using namespace spall;
using discretization::Field;

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream contents;
  contents << in.rdbuf();
  return contents.str();
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

class SurfaceIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) / (std::string("spall_surface_io_") + test->name() + "_" +
                                             std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

const std::vector<Vec3> points = {{0.1, -0.0, 1e-310},
                                  {std::numeric_limits<double>::max(), -1.0 / 3.0, 2.5},
                                  {-7.0, std::numeric_limits<double>::min(), 6.02214076e23}};

// The message of the InputError `f` throws.
template <typename F>
std::string input_error(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

}  // namespace

TEST_F(SurfaceIoTest, VtuReadsBackBitExactly) {
  const std::vector<discretization::Field> fields = {
      {"velocity", 3, std::vector<double>{1.5, -2, 0.1, 7, 8, 9, -3.25, 0, 1e-300}},
      {"part_id", 1, std::vector<std::int64_t>{1, std::numeric_limits<std::int64_t>::max(), -4}},
      {"stress", 6, std::vector<double>(18, 0.25), discretization::symmetric_tensor_components},
      {"a&b <\"odd\">", 1, std::vector<double>{1, 2, 3}}};
  io::output::write_vtu(dir_ / "d.vtu", points, fields);
  const auto snap = io::input::read_vtu(dir_ / "d.vtu");
  ASSERT_EQ(snap.points.size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    EXPECT_EQ(std::memcmp(snap.points[i].data(), points[i].data(), sizeof(Vec3)), 0) << "point " << i;
  ASSERT_EQ(snap.fields.size(), fields.size());
  for (std::size_t k = 0; k < fields.size(); ++k) {
    EXPECT_EQ(snap.fields[k].name, fields[k].name);
    EXPECT_EQ(snap.fields[k].components, fields[k].components);
    EXPECT_EQ(snap.fields[k].values, fields[k].values);
    EXPECT_EQ(snap.fields[k].component_names, fields[k].component_names);
  }
  EXPECT_EQ(snap.field("part_id"), &snap.fields[1]);
  EXPECT_EQ(snap.field("pressure"), nullptr);
}

TEST_F(SurfaceIoTest, VtuWithNoPointsReadsBack) {
  io::output::write_vtu(dir_ / "empty.vtu", {}, {{"pressure", 1, std::vector<double>{}}});
  const auto snap = io::input::read_vtu(dir_ / "empty.vtu");
  EXPECT_TRUE(snap.points.empty());
  ASSERT_EQ(snap.fields.size(), 1u);
  EXPECT_EQ(snap.fields[0].name, "pressure");
}

// An MPI run's output time: a .pvtu joining the ranks' pieces (one of them empty: a rank with no
// node), read back as the pieces one after another.
TEST_F(SurfaceIoTest, PvtuReadsBackItsPiecesInOrder) {
  const auto piece_fields = [](std::vector<double> pressure, std::vector<std::int64_t> id) {
    return std::vector<Field>{{"pressure", 1, std::move(pressure)}, {"node_id", 1, std::move(id)}};
  };
  fs::create_directories(dir_ / "d3plot_00003");
  io::output::write_vtu(dir_ / "d3plot_00003/d3plot_00003_0.vtu", {}, piece_fields({}, {}));
  io::output::write_vtu(dir_ / "d3plot_00003/d3plot_00003_1.vtu", {points[0], points[1]},
                        piece_fields({1.5, -2}, {10, 11}));
  io::output::write_vtu(dir_ / "d3plot_00003/d3plot_00003_2.vtu", {points[2]}, piece_fields({1e-300}, {12}));
  io::output::write_pvtu(dir_ / "d3plot_00003.pvtu",
                         {"d3plot_00003/d3plot_00003_0.vtu", "d3plot_00003/d3plot_00003_1.vtu",
                          "d3plot_00003/d3plot_00003_2.vtu"},
                         piece_fields({}, {}));
  const std::string pvtu = read_file(dir_ / "d3plot_00003.pvtu");
  EXPECT_NE(pvtu.find(R"(<PDataArray type="Float64" Name="pressure" NumberOfComponents="1"/>)"), std::string::npos);
  EXPECT_NE(pvtu.find(R"(<Piece Source="d3plot_00003/d3plot_00003_2.vtu"/>)"), std::string::npos);
  const auto snap = io::input::read_vtu(dir_ / "d3plot_00003.pvtu");
  ASSERT_EQ(snap.points.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_EQ(std::memcmp(snap.points[i].data(), points[i].data(), sizeof(Vec3)), 0) << "point " << i;
  EXPECT_EQ(std::get<std::vector<double>>(snap.field("pressure")->values), (std::vector<double>{1.5, -2, 1e-300}));
  EXPECT_EQ(std::get<std::vector<std::int64_t>>(snap.field("node_id")->values),
            (std::vector<std::int64_t>{10, 11, 12}));

  // A piece whose fields are not the first piece's is refused, naming it.
  io::output::write_vtu(dir_ / "d3plot_00003/d3plot_00003_2.vtu", {points[2]},
                        {{"density", 1, std::vector<double>{1}}, {"node_id", 1, std::vector<std::int64_t>{12}}});
  EXPECT_NE(input_error([&] { io::input::read_vtu(dir_ / "d3plot_00003.pvtu"); })
                .find("d3plot_00003_2.vtu: point field 'density' is not the first piece's 'pressure'"),
            std::string::npos);
}

TEST_F(SurfaceIoTest, PvdReadsBackTimesAndFiles) {
  io::output::PvdSeries series(dir_ / "d3plot.pvd");
  series.add(0.0, "d3plot_00000.vtu");
  series.add(1.0 / 3.0, "d3plot_00001.vtu");
  series.add(2.5e-4, "odd & name.vtu");
  const auto entries = io::input::read_pvd(dir_ / "d3plot.pvd");
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[1].time, 1.0 / 3.0);  // %.17g reads back to the same double
  EXPECT_EQ(entries[1].file, "d3plot_00001.vtu");
  EXPECT_EQ(entries[2].file, "odd & name.vtu");
}

TEST_F(SurfaceIoTest, ReaderRefusesWhatItCannotReadWithPathAndReason) {
  const fs::path path = dir_ / "d.vtu";
  EXPECT_NE(input_error([&] { io::input::read_vtu(path); }).find("d.vtu: cannot open"), std::string::npos);

  io::output::write_vtu(path, points, {{"pressure", 1, std::vector<double>{1, 2, 3}}});
  const std::string good = read_file(path);
  // Cut inside the points (after the pressure block of 8 + 24 bytes): the byte count no longer
  // fits the file.
  write_file(path, good.substr(0, good.find('_', good.find("<AppendedData")) + 1 + 32 + 40));
  EXPECT_NE(input_error([&] { io::input::read_vtu(path); }).find("ends inside"), std::string::npos);

  std::string compressed = good;
  compressed.replace(compressed.find("header_type"), 0, "compressor=\"vtkZLibDataCompressor\" ");
  write_file(path, compressed);
  EXPECT_NE(input_error([&] { io::input::read_vtu(path); }).find("compressed"), std::string::npos);

  std::string big_endian = good;
  big_endian.replace(big_endian.find("LittleEndian"), 12, "BigEndian");
  write_file(path, big_endian);
  EXPECT_NE(input_error([&] { io::input::read_vtu(path); }).find("byte_order=\"BigEndian\""), std::string::npos);

  std::string float32 = good;
  float32.replace(float32.find("type=\"Float64\" Name=\"pressure\""), 14, "type=\"Float32\"");
  write_file(path, float32);
  EXPECT_NE(input_error([&] { io::input::read_vtu(path); }).find("'pressure' is Float32"), std::string::npos);

  write_file(dir_ / "x.pvd", "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">\n<Collection>\n"
                             "<DataSet timestep=\"1,5\" file=\"a.vtu\"/>\n</Collection>\n</VTKFile>\n");
  EXPECT_NE(input_error([&] { io::input::read_pvd(dir_ / "x.pvd"); }).find("timestep=\"1,5\"> is not a number"),
            std::string::npos);
}

TEST_F(SurfaceIoTest, VtpHoldsTheTrianglesAndFields) {
  // A tetrahedron with a field on its vertices.
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<std::array<Index, 3>> t = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  io::output::write_vtp(dir_ / "s.vtp", v, t, {{"pressure", 1, std::vector<double>{1, 2, 3, 4}}});
  const std::string file = read_file(dir_ / "s.vtp");
  EXPECT_NE(file.find(R"(<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">)"),
            std::string::npos);
  EXPECT_NE(file.find(R"(NumberOfPoints="4")"), std::string::npos);
  EXPECT_NE(file.find(R"(NumberOfPolys="4")"), std::string::npos);
  // Appended blocks: pressure 4 doubles, points 12 doubles, connectivity 12 and offsets 4 Int64,
  // each after its 8-byte count; then the closing tags.
  const std::size_t underscore = file.find('_', file.find("<AppendedData"));
  const std::size_t data = (8 + 32) + (8 + 96) + (8 + 96) + (8 + 32);
  EXPECT_EQ(file.substr(underscore + 1 + data), "\n  </AppendedData>\n</VTKFile>\n");
  std::int64_t connectivity[12], offsets[4];
  std::memcpy(connectivity, file.data() + underscore + 1 + (8 + 32) + (8 + 96) + 8, sizeof connectivity);
  std::memcpy(offsets, file.data() + underscore + 1 + (8 + 32) + (8 + 96) + (8 + 96) + 8, sizeof offsets);
  EXPECT_EQ(connectivity[3], 0);
  EXPECT_EQ(connectivity[5], 3);
  EXPECT_EQ(connectivity[11], 3);
  EXPECT_EQ(offsets[0], 3);
  EXPECT_EQ(offsets[3], 12);

  EXPECT_THROW(io::output::write_vtp(dir_ / "bad.vtp", v, {{0, 1, 4}}, {}), std::invalid_argument);
  EXPECT_THROW(io::output::write_vtp(dir_ / "bad.vtp", v, t, {{"p", 1, std::vector<double>(3)}}),
               std::invalid_argument);
}

TEST_F(SurfaceIoTest, PlyHasTheHeaderAndBytesOfItsCounts) {
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<std::array<Index, 3>> t = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  io::output::write_ply(dir_ / "s.ply", v, t);
  const std::string file = read_file(dir_ / "s.ply");
  const std::string end = "end_header\n";
  const std::size_t body = file.find(end) + end.size();
  EXPECT_EQ(file.substr(0, 36), "ply\nformat binary_little_endian 1.0\n");
  EXPECT_NE(file.find("element vertex 4\n"), std::string::npos);
  EXPECT_NE(file.find("element face 4\nproperty list uchar int vertex_indices\n"), std::string::npos);
  EXPECT_EQ(file.size() - body, 4 * 12 + 4 * 13);  // float x y z; uchar 3 and three ints
  float last_z = 0;
  std::memcpy(&last_z, file.data() + body + 3 * 12 + 8, sizeof last_z);
  EXPECT_EQ(last_z, 1.0f);
  EXPECT_EQ(file[body + 4 * 12 + 3 * 13], 3);  // the last face has three corners
  EXPECT_THROW(io::output::write_ply(dir_ / "bad.ply", v, {{0, 1, -1}}), std::invalid_argument);
}
