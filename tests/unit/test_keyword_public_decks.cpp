// Every public deck in shared/decks/public (recursively, *.k) reads and validates without any
// exception other than InputError; what each gives is checked where known.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "keyword_test_decks.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/materials/make_material.hpp"

namespace spall::io::keyword {
namespace {

const std::filesystem::path public_decks =
    std::filesystem::path(SPALL_SHARED_DIR) / "decks" / "public";

// The public decks live in shared/ beside the checkout, which a user's clone does not have: the
// tests skip, saying so, when it is absent.
class keyword_public_decks : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::is_directory(public_decks))
      GTEST_SKIP() << public_decks.string() << " is absent (a clone without ../shared): skipped";
  }
};

TEST_F(keyword_public_decks, EveryDeckReadsOrFailsWithInputError) {
  int decks = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(public_decks)) {
    if (entry.path().extension() != ".k") continue;
    ++decks;
    // Recorded in the test log: what each deck gives, or the one line that refuses it.
    std::string outcome;
    try {
      const model::Model model = read_deck(entry.path());
      outcome = std::to_string(model.nodes.size()) + " nodes, " +
                std::to_string(model.solid_elements.size()) + " solids, " +
                std::to_string(model.sph_elements.size()) + " particles, " +
                std::to_string(model.unsupported.size()) + " unsupported keywords; ";
      try {
        validate(model);
        outcome += "valid";
      } catch (const InputError& error) {
        outcome += std::string("validate: ") + error.what();
      }
    } catch (const InputError& error) {
      outcome = std::string("read: ") + error.what();
    } catch (const std::exception& other) {
      ADD_FAILURE() << entry.path() << " threw something other than InputError: " << other.what();
    }
    std::cout << entry.path().lexically_relative(public_decks).string() << ": " << outcome << "\n";
  }
  EXPECT_GE(decks, 23);
}

TEST_F(keyword_public_decks, TaylorBarMesh) {
  const auto model = read_deck(public_decks / "ansys-example-data_taylor_bar_mesh.k");
  EXPECT_EQ(model.solid_elements.size(), 768u);
  EXPECT_EQ(model.nodes.size(), 1122u);
  EXPECT_TRUE(model.unsupported.empty());
  // Ten-node format with N9 = N10 = 0: every element is a hexahedron of existing nodes.
  EXPECT_EQ(model.solid_elements.front().eid, 1);
  EXPECT_EQ(model.nodes.front().x, Vec3(1.723924, 39.0625, -2.303499));
  // The mesh alone has no part or termination: validate says so with an InputError.
  EXPECT_THROW(validate(model), InputError);
}

// The deck's text without the blocks of the keywords whose names start with `prefix`.
std::string without_blocks(const std::filesystem::path& path, std::string_view prefix) {
  std::ifstream in(path, std::ios::binary);
  std::string line, text;
  bool skipping = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.front() == '*') skipping = line.starts_with(prefix);
    if (!skipping) text += line + "\n";
  }
  return text;
}

TEST_F(keyword_public_decks, BirdStrikeReadsItsParticlesFast) {
  // Its two contacts are segment-based (SOFT 2), which Spall refuses at the card; the rest of the
  // deck is read from a copy without them.
  const auto deck = public_decks / "ansys-example-data_bird_strike.k";
  EXPECT_EQ(test::input_error_of([&] { read_deck(deck); }),
            deck.lexically_normal().string() +
                ":20755: *CONTACT_AUTOMATIC_SINGLE_SURFACE_ID: field SOFT: '2' is not 0 (standard penalty) or 1 "
                "(soft constraint): segment-based contact (2) and the forming options (4, 6) are not implemented");
  test::DeckFolder folder;
  const auto copy = folder.write("bird_strike.k", without_blocks(deck, "*CONTACT_"));
  const auto start = std::chrono::steady_clock::now();
  const auto model = read_deck(copy);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 0.5);  // 1.2 MB: "well under a second"
  ASSERT_EQ(model.sph_elements.size(), 701u);
  EXPECT_EQ(model.sph_elements.front().mass, -15625.0);  // a volume
  EXPECT_EQ(model.sph_elements.front().pid, 6);
  const auto& section = std::get<model::SectionSph>(model.sections.at(6));
  EXPECT_EQ(section.cslh, 1.2);  // all fields 0 -> defaults
  EXPECT_EQ(section.hmax, 2.0);
  ASSERT_TRUE(model.termination);
  EXPECT_EQ(model.termination->endtim, 0.01);
  EXPECT_EQ(model.termination->endmas, 100000.0);
  EXPECT_EQ(model.initial_velocity_generations.at(0).v, Vec3(125000, 0, 0));
  EXPECT_EQ(model.node_sets.size(), 4u);
  EXPECT_EQ(model.part_sets.size(), 5u);
  EXPECT_EQ(model.segment_sets.size(), 2u);  // *SET_SEGMENT_TITLE 1 and 6, on the shells' nodes
  ASSERT_TRUE(model.control_contact);
  EXPECT_EQ(model.control_contact->slsfac, 0.1);  // 0 -> 0.1
  ASSERT_TRUE(model.rcforc);
  EXPECT_EQ(model.rcforc->dt, 0.01);
  // The water bird: *MAT_NULL 6 (RO 1e-9, PC 0) with *EOS_GRUNEISEN 6 (C 1483000, S1 1.75,
  // GAMMA0 0.28, card 2 all zero).
  const auto& water = std::get<model::MatNull>(model.materials.at(6).params);
  EXPECT_EQ(water.ro, 1.0e-9);
  EXPECT_EQ(water.pc, 0.0);
  EXPECT_EQ(water.mu, 0.0);
  const auto& eos = model.eos.at(6);
  EXPECT_EQ(eos.keyword, "*EOS_GRUNEISEN");
  EXPECT_EQ(eos.where.line, 220);
  const auto& gruneisen = std::get<model::EosGruneisen>(eos.params);
  EXPECT_EQ(gruneisen.c, 1483000.0);
  EXPECT_EQ(gruneisen.s1, 1.75);
  EXPECT_EQ(gruneisen.s2, 0.0);
  EXPECT_EQ(gruneisen.gamma0, 0.28);
  EXPECT_EQ(gruneisen.e0, 0.0);
  EXPECT_EQ(gruneisen.v0, 1.0);  // 0 -> 1
  EXPECT_EQ(gruneisen.lcid, 0);
  // The shells, their sections and materials stay unsupported, but no part with particles
  // uses them: the deck validates.
  EXPECT_NO_THROW(validate(model));
  const auto material = materials::make_material(model, *model.find_part(6));
  EXPECT_EQ(material.shear_modulus, 0.0);
  EXPECT_TRUE(std::holds_alternative<materials::Null>(material.strength));
  EXPECT_TRUE(std::holds_alternative<materials::Gruneisen>(material.eos));
  // Water at rest: p = 0 and c = C = 1483000 mm/s (*EOS_GRUNEISEN at mu = 0, E = 0).
  EXPECT_EQ(materials::eos_pressure(material, 1.0e-9, 0.0), 0.0);
  EXPECT_NEAR(materials::sound_speed(material, 1.0e-9, 0.0), 1483000.0, 1e-6);
}

TEST_F(keyword_public_decks, PydynaMechRunTogetherFields) {
  const auto model = read_deck(public_decks / "pydyna_mech.k");
  ASSERT_TRUE(model.termination);
  EXPECT_EQ(model.termination->endtim, 0.03);
  EXPECT_EQ(model.termination->endeng, 0.0);
  EXPECT_EQ(model.termination->endmas, 1.0e8);
  EXPECT_EQ(model.bulk_viscosity.type, -2);
  EXPECT_EQ(model.nodes.size(), 4u);
  EXPECT_EQ(model.parts.at(0).heading, "");  // blank heading line
  EXPECT_EQ(model.d3plot->dt, 5.0e-4);
  // *RIGIDWALL_PLANAR_ID 1: all nodes, DEATH and RWKSF 0 (-> 1e20, 1), normal +y, FRIC 0.5.
  ASSERT_EQ(model.rigid_walls.size(), 1u);
  const auto& wall = model.rigid_walls[0];
  EXPECT_EQ(wall.id, 1);
  EXPECT_EQ(wall.nsid, 0);
  EXPECT_EQ(wall.death, 1.0e20);
  EXPECT_EQ(wall.rwksf, 1.0);
  EXPECT_EQ(wall.head - wall.tail, Vec3(0, 1, 0));
  EXPECT_EQ(wall.fric, 0.5);
  ASSERT_TRUE(model.rwforc);
  EXPECT_EQ(model.rwforc->dt, 2.0e-4);
  EXPECT_EQ(model.rwforc->ioopt, 1);
}

TEST_F(keyword_public_decks, PydynaIsphRigidMaterialsAndMotion) {
  const auto model = read_deck(public_decks / "pydyna_isph.k");
  const auto& rigid = std::get<model::MatRigid>(model.materials.at(2).params);
  EXPECT_EQ(rigid.ro, 1.0e-9);  // `         21.00000E-9`: MID 2 and RO run together
  EXPECT_EQ(rigid.e, 10.0);
  EXPECT_EQ(std::get<model::SectionSph>(model.sections.at(4)).sphini, 12.0);
  ASSERT_FALSE(model.prescribed_motions.empty());
  EXPECT_EQ(model.prescribed_motions[0].target, model::Target::part);
  EXPECT_EQ(model.prescribed_motions[0].death, 1.0e28);  // 0 -> default
  ASSERT_EQ(model.body_loads.size(), 1u);
  EXPECT_EQ(model.body_loads[0].lcid, 4);
  EXPECT_EQ(model.timestep.tssfac, 1.0);
  EXPECT_EQ(model.timestep.lctm, 1);
}

}  // namespace
}  // namespace spall::io::keyword
