// *DEFINE_SPH_MESH_BOX: the particles it generates (cell-centred lattice, node IDs after the
// deck's, mass = -cell volume so that RO x volume is the mass) and every refusal, at its line.
#include <gtest/gtest.h>

#include "keyword_test_decks.hpp"
#include "spall/core/memory.hpp"
#include "spall/io/keyword/keyword_readers.hpp"
#include "spall/io/keyword/reader.hpp"

namespace spall::io::keyword {
namespace {

using test::DeckFolder;
using test::input_error_of;
using test::row;

const std::initializer_list<int> node_widths = {8, 16, 16, 16, 8, 8};

std::string deck_with_box(const std::string& card1, const std::string& card2,
                          const std::string& more = "") {
  return "*KEYWORD\n*NODE\n" + row({"7", "0.0", "0.0", "0.0"}, node_widths) +
         row({"41", "1.0", "0.0", "0.0"}, node_widths) + "*PART\nwater\n" + row({"3", "1", "1"}) +
         "*SECTION_SPH\n" + row({"1"}) + "*MAT_ELASTIC\n" + row({"1", "1000.0", "1.0e9"}) + more +
         "*DEFINE_SPH_MESH_BOX\n" + card1 + card2 + "*CONTROL_TERMINATION\n" + row({"1.0"});
}

std::string prefix(const DeckFolder& folder, int line) {
  return (folder.path() / "box.k").lexically_normal().string() + ":" + std::to_string(line) +
         ": *DEFINE_SPH_MESH_BOX: ";
}

TEST(keyword_sph_mesh_box, CellCentredParticlesAfterTheDecksNodes) {
  DeckFolder folder;
  const auto model = read_deck(folder.write(
      "box.k", deck_with_box(row({"1.0", "-2.0", "0.5", "0.4", "0.2", "0.3"}),
                             row({"3", "2", "1", "3", "", "0", "0.0"}))));
  ASSERT_EQ(model.sph_mesh_boxes.size(), 1u);
  const auto& box = model.sph_mesh_boxes[0];
  EXPECT_EQ(box.ipid, 3);
  EXPECT_EQ(box.nx, 2);
  EXPECT_EQ(box.nz, 3);
  ASSERT_EQ(model.nodes.size(), 2u + 6u);
  ASSERT_EQ(model.sph_elements.size(), 6u);
  // Cells 0.2 x 0.2 x 0.1: centres at x 1.1, 1.3; y -1.9; z 0.55, 0.65, 0.75; x fastest.
  const Vec3 expected[6] = {{1.1, -1.9, 0.55}, {1.3, -1.9, 0.55}, {1.1, -1.9, 0.65},
                            {1.3, -1.9, 0.65}, {1.1, -1.9, 0.75}, {1.3, -1.9, 0.75}};
  for (int k = 0; k < 6; ++k) {
    const auto& node = model.nodes[2 + k];
    EXPECT_EQ(node.id, 42 + k);  // the largest *NODE ID was 41
    EXPECT_LT((node.x - expected[k]).norm(), 1e-12) << k;
    const auto& particle = model.sph_elements[k];
    EXPECT_EQ(particle.nid, node.id);
    EXPECT_EQ(particle.pid, 3);
    EXPECT_NEAR(particle.mass, -0.2 * 0.2 * 0.1, 1e-15);  // a volume: RO x volume is the mass
  }
  EXPECT_NO_THROW(validate(model));
}

TEST(keyword_sph_mesh_box, SecondBoxNumbersOnAndPlaneStrainIsPerUnitThickness) {
  DeckFolder folder;
  const std::string second = "*DEFINE_SPH_MESH_BOX\n" + row({"0.0", "0.0", "-0.5", "1.0", "1.0", "1.0"}) +
                             row({"3", "1", "2", "1"});
  const auto model = read_deck(folder.write(
      "box.k", deck_with_box(row({"0.0", "0.0", "-0.5", "2.0", "1.0", "1.0"}), row({"3", "4", "1", "1"}),
                             "*CONTROL_SPH\n" + row({"", "", "", "2"}) + second)));
  ASSERT_EQ(model.sph_elements.size(), 2u + 4u);
  // The box written second in the file (IDs 42, 43) comes first; then the four of the last box.
  EXPECT_EQ(model.sph_elements[0].nid, 42);
  EXPECT_EQ(model.sph_elements[2].nid, 44);
  EXPECT_NEAR(model.sph_elements[2].mass, -0.5 * 1.0, 1e-15);  // cell area, not volume
  EXPECT_NEAR(model.nodes[4].x.z(), 0.0, 1e-15);              // at ZMIN + ZLEN / 2
}

TEST(keyword_sph_mesh_box, Refusals) {
  DeckFolder folder;
  const auto error = [&](const std::string& card1, const std::string& card2, const std::string& more = "") {
    const auto path = folder.write("box.k", deck_with_box(card1, card2, more));
    return input_error_of([&] { validate(read_deck(path)); });
  };
  const std::string box = row({"0.0", "0.0", "0.0", "1.0", "1.0", "1.0"});
  // Lines: the box's card 1 is line 13 of the deck, card 2 line 14.
  EXPECT_EQ(error(row({"0.0", "0.0", "0.0", "1.0", "0.0", "1.0"}), row({"3", "1", "1", "1"})),
            prefix(folder, 13) + "field YLEN: '0.0': the box needs a length > 0");
  EXPECT_EQ(error(box, row({"3", "1", "0", "1"})),
            prefix(folder, 14) + "field NY: '0': at least one particle per direction");
  EXPECT_EQ(error(box, row({"3", "1", "1", "1", "", "5", "1.0"})),
            prefix(folder, 14) +
                "field IDSEG: removing the particles near segment set 5 is not supported (leave IDSEG 0)");
  EXPECT_EQ(error(box, row({"9", "1", "1", "1"})), prefix(folder, 14) + "IPID: part 9 is not defined");
  EXPECT_EQ(error(box, row({"3", "1", "1", "2"}), "*CONTROL_SPH\n" + row({"", "", "", "2"})),
            prefix(folder, 16) + "NZ 2: in plane strain (*CONTROL_SPH IDIM 2) a box has one layer, NZ 1");
}

// Issue 36, resource limits: a generation whose particles would not fit in the memory left is
// refused at its card before anything is allocated (core/memory.hpp), not killed by the kernel.
// 10^9 particles at about 1.1 kB each (their model records and the run's 1 kB) are 1.1 TB, more
// than any machine this runs on has free.
TEST(keyword_sph_mesh_box, GenerationsBeyondTheMemoryLeftAreRefusedBeforeAllocating) {
  DeckFolder folder;
  const std::string box = row({"0.0", "0.0", "0.0", "1.0", "1.0", "1.0"});
  const auto path = folder.write("box.k", deck_with_box(box, row({"3", "1000", "1000", "1000"})));
  const std::string message = input_error_of([&] { validate(read_deck(path)); });
  // About 1 kB a particle for the run and its records in the model (particle_bytes, which the
  // records' sizes change).
  EXPECT_GT(particle_bytes, 1000);
  EXPECT_LT(particle_bytes, 1200);
  EXPECT_EQ(message.rfind(prefix(folder, 14) + "field NZ: NX x NY x NZ: 1e+09 particles need about " +
                              memory::human_bytes(1e9 * particle_bytes),
                          0),
            0u)
      << message;
  EXPECT_NE(message.find("available"), std::string::npos) << message;

  // *ELEMENT_SPH NEND: particles NID to NEND, all of one card; 10^8 of them (110 GB) against a
  // limit of 10 GB (`spall run --memory-limit 10`), so that the test does not depend on the machine.
  memory::set_limit(10'000'000'000);
  const auto nend = folder.write("nend.k", "*KEYWORD\n*PART\nwater\n" + row({"3", "1", "1"}) + "*SECTION_SPH\n" +
                                               row({"1"}) + "*MAT_ELASTIC\n" + row({"1", "1000.0", "1.0e9"}) +
                                               "*ELEMENT_SPH\n" + row({"1", "3", "1.0", "99999999"}, {8, 8, 16, 8}) +
                                               "*CONTROL_TERMINATION\n" + row({"1.0"}));
  const std::string nend_message = input_error_of([&] { validate(read_deck(nend)); });
  EXPECT_NE(nend_message.find("nend.k:10: *ELEMENT_SPH: field NEND: NID to NEND: 1e+08 particles need about 1"),
            std::string::npos)
      << nend_message;
  EXPECT_NE(nend_message.find("this machine has 10 GB available"), std::string::npos) << nend_message;
  memory::set_limit(0);
}

}  // namespace
}  // namespace spall::io::keyword
