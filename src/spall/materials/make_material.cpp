#include "spall/materials/make_material.hpp"

#include <fmt/format.h>

namespace spall::materials {

namespace {

Real bulk_modulus(Real e, Real pr) { return e / (3 * (1 - 2 * pr)); }
Real shear_modulus(Real e, Real pr) { return e / (2 * (1 + pr)); }

class MaterialMaker {
 public:
  MaterialMaker(const model::Model& model, const model::Part& part) : model_(model), part_(part) {
    const auto material = model.materials.find(part.mid);
    if (material == model.materials.end())
      fail_part(fmt::format("MID: material {} is not defined", part.mid));
    card_ = &material->second;
    if (part.eosid != 0) {
      const auto eos = model.eos.find(part.eosid);
      if (eos == model.eos.end())
        fail_part(fmt::format("EOSID: equation of state {} is not defined", part.eosid));
      eos_ = &eos->second;
    }
  }

  Material make() {
    Material material =
        std::visit([this](const auto& params) { return make(params); }, card_->params);
    if (eos_) set_eos(material);
    return material;
  }

 private:
  Material make(const model::MatElastic& card) {
    if (!(card.ro > 0) || !(card.e > 0) || card.pr < 0 || card.pr >= 0.5)
      fail_material(
          fmt::format("needs RO > 0, E > 0 and 0 <= PR < 0.5 (found RO {:g}, E {:g}, PR {:g})",
                      card.ro, card.e, card.pr));
    refuse_eos();
    return {card.ro, shear_modulus(card.e, card.pr), Elastic{},
            LinearBulk{bulk_modulus(card.e, card.pr)}};
  }

  Material make(const model::MatRigid&) {
    fail_material(fmt::format("material {} is a rigid body, not a deformable material (part {})",
                              card_->id, part_.id));
  }

  Material make(const model::MatPlasticKinematic& card) {
    refuse_eos();
    PlasticKinematic strength;
    strength.yield_stress = card.sigy;
    strength.hardening_modulus = card.e * card.etan / (card.e - card.etan);
    strength.beta = card.beta;
    strength.rate = {card.src, card.srp};
    strength.failure_strain = card.fs;
    return {card.ro, shear_modulus(card.e, card.pr), strength,
            LinearBulk{bulk_modulus(card.e, card.pr)}};
  }

  Material make(const model::MatPiecewiseLinearPlasticity& card) {
    refuse_eos();
    PiecewiseLinear strength;
    strength.curve = HardeningCurve(hardening_points(card));
    if (!(strength.curve.at(0).stress > 0))
      fail_material(
          fmt::format("the yield stress at zero plastic strain is {:g}; it must be positive",
                      strength.curve.at(0).stress));
    strength.rate = {card.c, card.p};
    strength.deviatoric_rate = card.vp == -1;
    // FAIL 0 means no failure, as does the default 1e21.
    strength.failure_strain = card.fail;
    return {card.ro, shear_modulus(card.e, card.pr), std::move(strength),
            LinearBulk{bulk_modulus(card.e, card.pr)}};
  }

  Material make(const model::MatJohnsonCook& card) {
    JohnsonCook strength;
    strength.a = card.a;
    strength.b = card.b;
    strength.n = card.n;
    strength.c = card.c;
    strength.m = card.m;
    strength.melt_temperature = card.tm;
    strength.room_temperature = card.tr;
    strength.reference_rate = card.epso;
    strength.heat_capacity = card.cp;
    strength.d1 = card.d1;
    strength.d2 = card.d2;
    strength.d3 = card.d3;
    strength.d4 = card.d4;
    strength.d5 = card.d5;
    strength.min_failure_strain = card.efmin;
    strength.erode_at_failure = card.erod == 0;
    // LS-DYNA reads E and PR for shells; for solids the bulk response comes from the EOS.
    // Without one, Spall takes the linear K = E / (3 (1 - 2 PR)).
    if (!eos_ && card.e == 0)
      fail_part(
          fmt::format("material {} (*MAT_JOHNSON_COOK) has E = 0 and the part has no EOSID: "
                      "no bulk modulus",
                      card_->id));
    Material material{card.ro, card.g, strength,
                      LinearBulk{eos_ ? 0 : bulk_modulus(card.e, card.pr)}};
    material.tensile_limit = card.spall == 1   ? TensileLimit::pressure_cutoff
                             : card.spall == 2 ? TensileLimit::principal_stress
                                               : TensileLimit::hydrostatic_tension;
    material.pressure_cutoff = card.pc;
    material.initial_temperature = card.tr;
    return material;
  }

  Material make(const model::MatNull& card) {
    if (!eos_)
      fail_part(fmt::format("material {} (*MAT_NULL) needs an equation of state, but EOSID is 0",
                            card_->id));
    Material material{card.ro, 0, Null{card.mu}, LinearBulk{}};
    // PC = 0 leaves no tension at all.
    material.tensile_limit = TensileLimit::pressure_cutoff;
    material.pressure_cutoff = card.pc;
    return material;
  }

  std::vector<std::pair<Real, Real>> hardening_points(
      const model::MatPiecewiseLinearPlasticity& card) {
    if (card.lcss != 0) {
      const auto curve = model_.curves.find(card.lcss);
      if (curve == model_.curves.end())
        fail_material(fmt::format("LCSS: curve {} is not defined", card.lcss));
      const model::Curve& c = curve->second;
      if (!(c.sfa > 0))
        fail_material(fmt::format("LCSS: curve {} has SFA {:g}; the plastic strains must increase",
                                  c.id, c.sfa));
      // *DEFINE_CURVE's scaling: eps_p = SFA a + OFFA, sigma_y = SFO o + OFFO.
      std::vector<std::pair<Real, Real>> points;
      for (const auto& [a, o] : c.points)
        points.emplace_back(c.sfa * a + c.offa, c.sfo * o + c.offo);
      return points;
    }
    if (!card.points.empty()) return card.points;
    const Real hardening = card.e * card.etan / (card.e - card.etan);
    return {{0, card.sigy}, {1, card.sigy + hardening}};
  }

  void set_eos(Material& material) const {
    const Real rho0 = material.density;
    struct Visitor {
      Material& material;
      Real rho0;
      void operator()(const model::EosLinearPolynomial& card) const {
        material.eos = LinearPolynomial{card.c};
        material.initial_specific_energy = card.e0 / rho0;
      }
      void operator()(const model::EosGruneisen& card) const {
        material.eos = Gruneisen{card.c, card.s1, card.s2, card.s3, card.gamma0, card.a};
        material.initial_specific_energy = card.e0 / rho0;
      }
      void operator()(const model::EosMurnaghan& card) const {
        material.eos = Murnaghan{card.gamma, card.k0};
      }
    };
    std::visit(Visitor{material, rho0}, eos_->params);
  }

  // MAT_001, 003 and 024 compute their pressure from E and PR; LS-DYNA gives them no EOS.
  void refuse_eos() const {
    if (eos_)
      fail_part(
          fmt::format("EOSID {}: {} computes its own pressure (K = E / (3 (1 - 2 PR))) and "
                      "takes no equation of state",
                      part_.eosid, card_->keyword));
  }

  [[noreturn]] void fail_part(const std::string& message) const {
    throw InputError(part_.where, "*PART", fmt::format("part {}: {}", part_.id, message));
  }
  [[noreturn]] void fail_material(const std::string& message) const {
    throw InputError(card_->where, card_->keyword, message);
  }

  const model::Model& model_;
  const model::Part& part_;
  const model::Material* card_ = nullptr;
  const model::Eos* eos_ = nullptr;
};

}  // namespace

Material make_material(const model::Model& model, const model::Part& part) {
  return MaterialMaker(model, part).make();
}

}  // namespace spall::materials
