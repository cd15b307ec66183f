#pragma once
// The problem as read from a deck: nodes, elements, parts, sections, materials, sets, curves,
// boundary and initial conditions, controls and output requests. Plain data in the deck's own
// IDs and units; the solver builds its dense stores from it. Every item remembers where it was
// read, so that a later check can still say `file:line: *KEYWORD: ...`.
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "spall/core/error.hpp"
#include "spall/core/types.hpp"
#include "spall/model/curve.hpp"

namespace spall::model {

struct Node {
  Id id = 0;
  Vec3 x = Vec3::Zero();
  int tc = 0;  // translational constraint code (*NODE TC)
  int rc = 0;  // rotational constraint code (*NODE RC)
  SourceLocation where;
};

// *PART_INERTIA: a rigid part's mass properties, in place of those of its elements (fem-contact.md
// §1.5). The tensor's entries IXX IXY IXZ IYY IYZ IZZ are the inertia tensor's (the manual's "xy
// component of the inertia tensor"), about the centre, in global axes (IRCS 0) or in the local axes
// local_x, local_in_plane (IRCS 1).
struct PartInertia {
  Vec3 centre = Vec3::Zero();  // XC YC ZC
  Real mass = 0;               // TM
  Id node = 0;                 // NODEID: the centre is this node's position instead (0: none)
  Mat3 tensor = Mat3::Zero();
  bool local = false;          // IRCS 1
  Vec3 local_x = Vec3::Zero(), local_in_plane = Vec3::Zero();  // XL YL ZL, XLIP YLIP ZLIP
  Id cid = 0;                  // CID: the local axes from a coordinate system instead
  Vec3 velocity = Vec3::Zero(), angular_velocity = Vec3::Zero();  // VTX VTY VTZ, VRX VRY VRZ
  SourceLocation where;        // card 3
};

struct Part {
  Id id = 0;
  std::string heading;
  Id secid = 0;
  Id mid = 0;
  Id eosid = 0;
  Id hgid = 0;
  Id tmid = 0;  // a thermal material (*MAT_THERMAL_*), used only by a thermal or coupled solution
  std::optional<PartInertia> inertia;  // *PART_INERTIA
  SourceLocation where;
};

// *DEFINE_COORDINATE_SYSTEM, _VECTOR or _NODES: the axes of a local system, from a vector along one
// local axis and a vector in the plane of that axis and the next (x-y for x, y-z for y, z-x for z).
// Spall applies every card in global axes, so a card that names a system runs only when the
// system's axes are the global ones; its origin does not matter for directions.
struct CoordinateSystem {
  Id id = 0;
  std::string keyword;  // as written, e.g. *DEFINE_COORDINATE_VECTOR
  int axis_index = 0;   // which local axis `axis` is: 0 x, 1 y, 2 z (_NODES DIR)
  Vec3 axis = Vec3::Zero();
  Vec3 in_plane = Vec3::Zero();
  std::array<Id, 3> nodes{};  // _NODES: N1 N2 N3; axis = N1 -> N2, in_plane = N1 -> N3, from their coordinates
  bool follows_nodes = false;  // _NODES FLAG 1: the axes turn with the nodes during the run
  SourceLocation where;
};

// *DEFINE_VECTOR: a direction, from the tail (XT YT ZT) to the head (XH YH ZH), in the axes of the
// coordinate system CID (0: global).
struct Vector {
  Id id = 0;
  Vec3 tail = Vec3::Zero(), head = Vec3::Zero();
  Id cid = 0;
  SourceLocation where;
};

// A *MAT_THERMAL_* card: its own ID space in LS-DYNA (*PART TMID), apart from the structural
// materials. Spall solves no heat equation, so only the ID is kept, for TMID references.
struct ThermalMaterial {
  Id id = 0;
  std::string keyword;  // as written, e.g. *MAT_THERMAL_ISOTROPIC_TITLE
  SourceLocation where;
};

// *SECTION_SOLID: ELFORM 1 (constant stress hex) by default.
struct SectionSolid {
  Id id = 0;
  int elform = 1;
  int aet = 0;
  SourceLocation where;
};

// *SECTION_SPH. LS-DYNA's smoothing length is h = CSLH * (initial particle spacing); the kernel's
// support radius is 2h. SPHINI > 0 sets the initial h directly.
struct SectionSph {
  Id id = 0;
  Real cslh = 1.2;
  Real hmin = 0.2;
  Real hmax = 2.0;
  Real sphini = 0.0;
  Real death = 1.0e20;
  Real start = 0.0;
  int sphkern = 0;  // 0 cubic spline, 1 quintic, 2 quadratic, 3 quartic
  SourceLocation where;
};

// *SECTION_SOLID_SPG (ELFORM 47): the Smoothed Particle Galerkin method on the nodes of a solid
// mesh. Fields as read, with the manual's KERNEL-dependent defaults already applied to DX DY DZ,
// SMSTEP and ITB. Card 2 column 6 is LSCALE in R9-R11 manuals (unused now); column 8 is SWTIME in
// R9-R11 and MSC (ITB 3 only) now, kept as read in `column8`.
struct SectionSolidSpg {
  Id id = 0;
  int elform = 47;
  int aet = 0;
  Real cohoff = 0, gaskett = 0;
  Real dx = 1.6, dy = 1.6, dz = 1.6;  // normalized dilation parameters of the kernel
  int ispline = 0;  // 0 cubic spline, cubical support; 1 quadratic spline, cubical; 2 cubic, spherical
  int kernel = 0;   // 0 updated Lagrangian, 1 Eulerian, 2 pseudo-Lagrangian
  Real lscale = 0;
  int smstep = 15;  // kernel update interval in time steps
  Real column8 = 0;  // SWTIME (ITB 1, 2) or MSC (ITB 3)
  int idam = 1;      // bond-failure quantity: 1 effective plastic strain
  Real fs = 1.0e10;  // critical value of the IDAM quantity (1e10: no failure)
  Real stretch = 1.0;  // critical relative stretch of a bond (>= 1)
  int itb = 1;       // stabilization: 1 fluid particle, 2 simplified, 3 momentum-consistent
  Real msfac = 0;
  int isc = 0;
  Id boxid = 0;
  Real pdamp = -0.001;
  SourceLocation where;         // card 1
  SourceLocation where_card2;   // DX ... column 8
  SourceLocation where_card3;   // IDAM ... PDAMP (absent in decks that end after card 2)
};

// *SECTION_SHELL: Spall runs shells only as rigid geometry (*MAT_RIGID parts): the thickness gives
// their mass and their contact surface's offset, MAREA a mass per area. A rigid part has no
// deformation, so the formulation and integration fields (ELFORM, SHRF, NIP, PROPT, QR, ICOMP ...)
// are read for the layout and otherwise unused.
struct SectionShell {
  Id id = 0;
  int elform = 2;
  std::array<Real, 4> t{};  // T1-T4, the thickness at N1-N4 (blank T2-T4 take T1)
  Real marea = 0;           // non-structural mass per unit area
  SourceLocation where;     // card 1
  SourceLocation where_card2;
};

using Section = std::variant<SectionSolid, SectionSph, SectionSolidSpg, SectionShell>;

// *MAT_ELASTIC (001)
struct MatElastic {
  Real ro = 0, e = 0, pr = 0, da = 0, db = 0;
};
// *MAT_RIGID (020)
struct MatRigid {
  Real ro = 0, e = 0, pr = 0;
  Real n = 0, couple = 0, m = 0, alias = 0;
  Real cmo = 0;
  int con1 = 0, con2 = 0;
};

// LS-DYNA's constraint code (*NODE TC, *MAT_RIGID CON1 and CON2): 1 x, 2 y, 3 z, 4 xy, 5 yz, 6 zx,
// 7 xyz; as a mask, bit d set when axis d is held (0 for a code outside 0..7).
inline std::uint8_t constraint_axes(int code) {
  static constexpr std::uint8_t masks[8] = {0, 1, 2, 4, 3, 6, 5, 7};
  return (code >= 0 && code <= 7) ? masks[code] : 0;
}
// *MAT_PLASTIC_KINEMATIC (003): bilinear hardening, BETA 0 kinematic .. 1 isotropic, optional
// Cowper-Symonds rate scaling (SRC, SRP) and failure strain FS.
struct MatPlasticKinematic {
  Real ro = 0, e = 0, pr = 0, sigy = 0, etan = 0, beta = 0;
  Real src = 0, srp = 0, fs = 0;
  int vp = 0;
};
// *MAT_PIECEWISE_LINEAR_PLASTICITY (024): yield stress versus effective plastic strain from the
// curve LCSS, or from the EPS/ES points, or from SIGY and ETAN.
struct MatPiecewiseLinearPlasticity {
  Real ro = 0, e = 0, pr = 0, sigy = 0, etan = 0;
  Real fail = 1.0e21, tdel = 0;
  Real c = 0, p = 0;
  Id lcss = 0, lcsr = 0;
  int vp = 0;
  std::vector<std::pair<Real, Real>> points;  // (EPSi, ESi) given on cards 3-4, in order
};
// *MAT_JOHNSON_COOK (015)
struct MatJohnsonCook {
  Real ro = 0, g = 0, e = 0, pr = 0, dtf = 0;
  int vp = 0, rateop = 0;
  Real a = 0, b = 0, n = 0, c = 0, m = 0, tm = 0, tr = 0, epso = 0;
  Real cp = 0, pc = 0;
  int spall = 2, it = 0;
  Real d1 = 0, d2 = 0, d3 = 0, d4 = 0, d5 = 0;
  Real c2 = 0, erod = 0, efmin = 1.0e-6, numint = 0, k = 0, eps1 = 0;
};
// *MAT_NULL (009): no strength; pressure from the part's EOS.
struct MatNull {
  Real ro = 0, pc = 0, mu = 0, terod = 0, cerod = 0, ym = 0, pr = 0;
};
struct Material {
  Id id = 0;
  std::string keyword;  // e.g. "*MAT_ELASTIC", for messages
  std::variant<MatElastic, MatRigid, MatPlasticKinematic, MatPiecewiseLinearPlasticity,
               MatJohnsonCook, MatNull>
      params;
  SourceLocation where;
  Real density() const {
    return std::visit([](const auto& p) { return p.ro; }, params);
  }
};

// *EOS_LINEAR_POLYNOMIAL: p = C0 + C1 mu + C2 mu^2 + C3 mu^3 + (C4 + C5 mu + C6 mu^2) E.
struct EosLinearPolynomial {
  std::array<Real, 7> c{};
  Real e0 = 0, v0 = 1;
};
// *EOS_GRUNEISEN: Mie-Grueneisen with a cubic shock-velocity fit.
struct EosGruneisen {
  Real c = 0, s1 = 0, s2 = 0, s3 = 0, gamma0 = 0, a = 0, e0 = 0;
  Real v0 = 1;
  Id lcid = 0;
};
// *EOS_MURNAGHAN: p = K0 ((rho / rho0)^GAMMA - 1).
struct EosMurnaghan {
  Real gamma = 0, k0 = 0, v0 = 1;
};
struct Eos {
  Id id = 0;
  std::string keyword;  // e.g. "*EOS_GRUNEISEN", for messages
  std::variant<EosLinearPolynomial, EosGruneisen, EosMurnaghan> params;
  SourceLocation where;
};

// *ELEMENT_SPH: one particle at node `nid`. mass > 0 is a mass; mass < 0 is a volume, whose
// mass is |mass| times the density of the part's material.
struct ElementSph {
  Id nid = 0;
  Id pid = 0;
  Real mass = 0;
  SourceLocation where;
};

// *ELEMENT_SOLID: hexahedron (degenerate shapes repeat nodes).
struct ElementSolid {
  Id eid = 0;
  Id pid = 0;
  std::array<Id, 8> n{};
  SourceLocation where;

  // LS-DYNA's tetrahedron on a hexahedron card: N4 repeated in N5-N8.
  bool is_tetrahedron() const { return n[4] == n[3] && n[5] == n[3] && n[6] == n[3] && n[7] == n[3]; }
};

// *ELEMENT_SHELL (_THICKNESS, _BETA, _MCID): a quadrilateral N1-N4, a triangle repeating N3 as N4.
// thickness: THIC1-THIC4 of _THICKNESS/_BETA, 0 where the section's T1-T4 apply.
struct ElementShell {
  Id eid = 0;
  Id pid = 0;
  std::array<Id, 4> n{};
  std::array<Real, 4> thickness{};
  SourceLocation where;

  bool is_triangle() const { return n[3] == n[2]; }
};

// *DEFINE_SPH_MESH_BOX: the box [XMIN, XMIN + XLEN] x [YMIN, ...] x [ZMIN, ...] cut into
// NX x NY x NZ equal cells, one particle of part IPID at the centre of each (see
// io/keyword/sph_mesh_box.cpp for the node IDs and masses the reader gives them).
struct SphMeshBox {
  Vec3 lower = Vec3::Zero();   // XMIN YMIN ZMIN
  Vec3 length = Vec3::Zero();  // XLEN YLEN ZLEN
  Id ipid = 0;
  int nx = 0, ny = 0, nz = 0;
  Id idseg = 0;   // segment set that removes particles near it (0: none)
  Real sfsp = 0;  // with IDSEG: removal distance as a multiple of the spacing
  SourceLocation where;
};

// *SET_NODE_LIST_GENERATE's ranges are kept as read, and added to `nodes` once the whole deck is
// read and its nodes are known: a range cannot hold more IDs than there are nodes.
struct NodeRange {
  Id first = 0, last = 0;
  int line = 0;  // of the range's card, in the set's file
  const char* field = "";  // its first field's name, B1BEG .. B4BEG, for messages
};
struct NodeSet {
  Id id = 0;
  std::vector<Id> nodes;
  std::vector<NodeRange> ranges;
  SourceLocation where;
};
struct PartSet {
  Id id = 0;
  std::vector<Id> parts;
  SourceLocation where;
};
// *SET_SOLID: solid element IDs in the deck's order.
struct SolidSet {
  Id id = 0;
  std::vector<Id> elements;
  SourceLocation where;
};

// Which nodes a boundary condition or initial condition applies to.
enum class Target { node, node_set, part, part_set, all_nodes };

// *BOUNDARY_SPC_NODE / _SET: dof[0..5] = x y z rx ry rz fixed.
struct Spc {
  Target target = Target::node;
  Id id = 0;
  Id cid = 0;
  std::array<bool, 6> dof{};
  SourceLocation where;
};

// *BOUNDARY_PRESCRIBED_MOTION_NODE / _SET (/ _RIGID read but rejected by the solver for now).
struct PrescribedMotion {
  Target target = Target::node;
  Id id = 0;
  int dof = 0;  // 1 x, 2 y, 3 z, 4 vector VID, 5-7 rotations, ...
  int vad = 0;  // 0 velocity, 1 acceleration, 2 displacement
  Id lcid = 0;
  Real sf = 1.0;
  Id vid = 0;
  Real death = 1.0e28;
  Real birth = 0.0;
  SourceLocation where;
};

// *INITIAL_VELOCITY (nsid 0 = all nodes; nodes of set nsidex get v_exempt instead).
struct InitialVelocity {
  Id nsid = 0;
  Id nsidex = 0;
  Id boxid = 0;
  Vec3 v = Vec3::Zero();
  Vec3 vr = Vec3::Zero();
  Vec3 v_exempt = Vec3::Zero();
  Vec3 vr_exempt = Vec3::Zero();
  int irigid = 0;  // IRIGID: how rigid parts take the velocity (0 as their nodes)
  Id icid = 0;     // ICID: velocities given in this local coordinate system (0 global)
  SourceLocation where;
};
// *INITIAL_VELOCITY_NODE
struct InitialVelocityNode {
  Id nid = 0;
  Vec3 v = Vec3::Zero();
  Vec3 vr = Vec3::Zero();
  Id icid = 0;
  SourceLocation where;
};
// *INITIAL_VELOCITY_GENERATION: translation plus rotation OMEGA about the axis through xc along n.
struct InitialVelocityGeneration {
  Id id = 0;
  int styp = 2;  // 1 part set, 2 part, 3 node set
  Real omega = 0;
  Vec3 v = Vec3::Zero();
  Id ivatn = 0;
  Id icid = 0;
  Vec3 xc = Vec3::Zero();
  Vec3 axis = Vec3::Zero();
  int phase = 0;
  int irigid = 0;
  SourceLocation where;
};

// *LOAD_BODY_X/Y/Z: base acceleration a(t) = SF * curve(t) along `direction` (0 x, 1 y, 2 z).
// As in LS-DYNA, the body force on a node is -m a(t): gravity along -z is a positive LOAD_BODY_Z.
struct BodyLoad {
  int direction = 0;
  Id lcid = 0;
  Real sf = 1.0;
  Id lciddr = 0;
  Vec3 xc = Vec3::Zero();
  Id cid = 0;
  SourceLocation where;
};

// *RIGIDWALL_PLANAR (_MOVING, _FINITE, _FINITE_MOVING; each with _ID): a rigid plane through
// the tail point, its normal from tail to head pointing to the side where the tracked nodes are.
// *CONSTRAINED_RIGID_BODIES: rigid part PIDC moves as one body with rigid part PIDL (its lead).
struct ConstrainedRigidBodies {
  Id lead = 0;         // PIDL
  Id constrained = 0;  // PIDC
  SourceLocation where;
};

struct RigidWallPlanar {
  Id id = 0;  // the _ID card's ID; 0 when the keyword has no _ID card
  std::string title;
  Id nsid = 0;    // tracked nodes; 0 = all nodes
  Id nsidex = 0;  // nodes exempted from tracking
  Id boxid = 0;
  Real offset = 0;  // > 0: only nodes within this normal distance of the wall are tracked
  Real birth = 0;
  Real death = 1.0e20;
  Real rwksf = 1.0;
  Vec3 tail = Vec3::Zero();
  Vec3 head = Vec3::Zero();
  Real fric = 0;  // 0 frictionless, (0, 1) Coulomb coefficient, 1 no sliding, 2 and 3 welding
  Real wvel = 0;  // normal impact speed above which a node welds (FRIC 2, 3)
  bool finite = false;              // _FINITE: a rectangle with corner at the tail
  Vec3 edge_head = Vec3::Zero();    // XHEV YHEV ZHEV: head of the edge vector l (tail at XT YT ZT)
  Real lenl = 0, lenm = 0;          // extents along l and m = n x l; 0 = unbounded that way
  bool moving = false;              // _MOVING: a rigid body of mass MASS moving along n
  Real mass = 0;
  Real v0 = 0;  // initial velocity along n
  std::string keyword;  // as written (e.g. "*RIGIDWALL_PLANAR_MOVING_ID"), for messages
  SourceLocation where;
};

// *SET_SEGMENT: quadrilaterals N1 N2 N3 N4 in the deck's order (a triangle repeats N3 as N4).
struct SegmentSet {
  Id id = 0;
  std::vector<std::array<Id, 4>> segments;
  SourceLocation where;
};

// One side of a contact: SURFA/SURFATYP or SURFB/SURFBTYP.
struct ContactSurface {
  enum class Type { segment_set = 0, part_set = 2, part = 3, node_set = 4, all = 5, exempted_part_set = 6 };
  Id id = 0;  // the set's or part's ID (unused for `all`)
  Type type = Type::segment_set;
  SourceLocation where;  // card 1
};

// *CONTACT_NODES_TO_SURFACE, *CONTACT_AUTOMATIC_NODES_TO_SURFACE, *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE
// and *CONTACT_AUTOMATIC_SINGLE_SURFACE (with _ID, _TITLE, _MPP), and the *CONTACT_ERODING_ forms of
// the last three: penalty contact (SOFT 0, 1) with Coulomb friction. Fields as read, LS-DYNA's
// defaults applied (blank and 0 read alike where the manual says so: SFSA, SFSB, FSF, VSF 0 -> 1;
// DT 0 -> 1e20; SOFSCL 0 -> 0.1; MAXPAR 0 -> 1.025).
struct Contact {
  enum class Kind { nodes_to_surface, automatic_nodes_to_surface, automatic_surface_to_surface,
                    automatic_single_surface };
  Kind kind = Kind::automatic_nodes_to_surface;
  std::string keyword;  // as written, e.g. "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_ID", for messages
  Id id = 0;            // CID of the _ID card; 0 without one (then numbered in deck order)
  std::string heading;
  ContactSurface a, b;  // SURFA (slave nodes), SURFB (master segments); b unused for single surface
  Real fs = 0, fd = 0, dc = 0, vc = 0;  // Coulomb: mu = FD + (FS - FD) exp(-DC |v_rel|); VC caps F_t
  Real vdc = 0;                         // normal damping, percent of critical
  Real birth = 0, death = 1e20;         // BT, DT
  Real sfsa = 1, sfsb = 1;              // penalty scale of side A (nodes), side B (segments)
  Real fsf = 1, vsf = 1;                // scale of the Coulomb coefficients, of VC
  Real sast = 0, sbst = 0;              // contact thickness of side A's, B's shells (0: their own)
  Real sfsat = 1, sfsbt = 1;            // scale of that thickness
  int shlthk = -1;                      // optional card B; -1: *CONTROL_CONTACT's
  int soft = 0;                         // optional card A: 0 standard penalty, 1 soft constraint
  Real sofscl = 0.1;
  Real maxpar = 1.025;                  // parametric tolerance of the segment search
  int bsort = 0;                        // cycles between bucket sorts (Spall sorts every cycle)
  Real penmax = 0;                      // optional card B; 0: the type's default (automatic: 0.4)
  Real sldstf = 0;                      // > 0: the stiffness modulus of solid segments instead of K
  Real dtstif = 0;                      // optional card C: the step of the SOFT 1 stiffness (0: the first)
  // *CONTACT_ERODING_...: the automatic type of the same name whose surfaces follow element erosion
  // (card 4 ISYM EROSOP IADJ). EROSOP 1: an element face inside the body becomes a segment once the
  // element on its other side has eroded; IADJ 1: a face a side's element shares with another
  // part's element is a segment from the start (the side's boundary, not only the body's).
  bool eroding = false;
  int erosop = 0, iadj = 0;
  // ISYM 1 (card 4 of the eroding types, optional card B): the faces of solid elements on a
  // symmetry plane (every corner held along the face's normal) are no segments. -1: not given,
  // *CONTROL_CONTACT's.
  int isym = -1;
  SourceLocation where;                 // card 1
  SourceLocation where_card2, where_card3;
};

// *DATABASE_RCFORC_MOMENT: the nodes about which rcforc.csv takes contact CID's moments on side
// A (NODESA) and side B (NODESB); 0: the default point (the side's rigid-body centre, or the origin).
struct RcforcMoment {
  Id cid = 0;
  Id nodes_a = 0, nodes_b = 0;
  SourceLocation where;
};

// *CONTROL_CONTACT: the defaults every contact shares.
struct ControlContact {
  Real slsfac = 0.1;  // scale of the penalty stiffness (0 -> 0.1)
  int penopt = 1;     // 1: the smaller of node and segment stiffness; 2: segment; 3: node
  Real xpene = 4.0;   // release depth of *CONTACT_NODES_TO_SURFACE, in segment thicknesses (0 -> 4)
  int shlthk = 0;     // shell thickness in *CONTACT_NODES_TO_SURFACE: 0 no, 1 not of rigid shells, 2 yes
  // Card 4 IGNORE: the contacts' default for tracking initial penetrations (not implemented). Kept
  // so that validate() refuses it only in a deck that has a contact for it to act on.
  int ignore = 0;
  int isym = 0;  // card 5: the contacts' default ISYM
  SourceLocation where;
};

struct ControlTermination {
  Real endtim = 0;
  int endcyc = 0;  // 0 = no limit
  Real dtmin = 0;
  Real endeng = 0;
  Real endmas = 1.0e8;
  SourceLocation where;
};

struct ControlTimestep {
  Real dtinit = 0;
  Real tssfac = 0.9;
  int isdo = 0;
  Real tslimt = 0;
  Real dt2ms = 0;
  Id lctm = 0;
  int erode = 0;  // ERODE: 1 in the units digit erodes solids whose step falls below DTMIN dt0
  int ms1st = 0;
  SourceLocation where;
};

// An output request: *DATABASE_BINARY_D3PLOT (field output), *DATABASE_GLSTAT (energies) or
// *DATABASE_RWFORC (rigid-wall forces).
struct OutputInterval {
  Real dt = 0;
  Id lcdt = 0;    // D3PLOT LCDT / GLSTAT LCUR: curve of the output interval versus time
  int beam = 0;   // D3PLOT BEAM (discrete-element output flag; kept for completeness)
  int npltc = 0;  // D3PLOT: DT = ENDTIM / NPLTC when DT is 0
  int ioopt = 0;  // RWFORC: how LCUR sets the next output time (1: now + LCUR(now))
  SourceLocation where;
};

// A card of *DATABASE_HISTORY_NODE (_SET) or *DATABASE_HISTORY_SOLID: the node IDs (node set IDs)
// whose motion nodout.csv follows at the *DATABASE_NODOUT interval, or the solid element IDs whose
// stress elout.csv follows at the *DATABASE_ELOUT interval.
struct HistoryIds {
  std::vector<Id> ids;
  bool sets = false;     // _SET: the IDs are sets' (node sets, solid sets)
  SourceLocation where;  // the card's
};

// *DATABASE_BINARY_RUNRSF: a running restart file every CYCL steps; NR files written in turn
// (1: one file, overwritten), so that a crash while one is written leaves the one before.
struct RestartOutput {
  std::int64_t cycles = 0;  // CYCL
  int files = 1;            // NR
  SourceLocation where;
};

// *DAMPING_GLOBAL: mass-weighted nodal damping f = -D m v, D = VALDMP or the curve LCID of time;
// STX STY STZ scale it per direction (all six scale factors 0: all 1).
struct DampingGlobal {
  Id lcid = 0;
  Real valdmp = 0;
  Vec3 translation_scale = Vec3::Ones();  // STX STY STZ
  Vec3 rotation_scale = Vec3::Zero();     // SRX SRY SRZ (no rotational degrees of freedom in Spall)
  SourceLocation where;
};

// *CONTROL_BULK_VISCOSITY: quadratic (Q1) and linear (Q2) artificial-viscosity coefficients.
// Spall's SPH uses them as Monaghan's beta = Q1 and alpha = Q2, as LS-DYNA's SPH does.
struct ControlBulkViscosity {
  Real q1 = 1.5;
  Real q2 = 0.06;
  int type = 1;
  SourceLocation where;
};

// *MAT_ADD_EROSION: failure criteria added to material MID; an element whose NCS criteria hold
// at once (at NUMFIP of its integration points) is deleted. A criterion whose value equals EXCL
// is off (blank and 0 read as 0, so with the default EXCL 0 the blank ones are off).
struct MatAddErosion {
  Id mid = 0;
  Real excl = 0;
  Real mxpres = 0, mneps = 0, effeps = 0, voleps = 0;  // card 1
  Real numfip = 1, ncs = 1;
  Real mnpres = 0, sigp1 = 0, sigvm = 0, mxeps = 0, epssh = 0, sigth = 0, impulse = 0, failtm = 0;  // card 2
  SourceLocation where;
};

// *HOURGLASS (HGID on *PART): the hourglass control of one-point solid elements and the bulk
// viscosity of the part's elements. 0 in IHQ, Q1 or Q2 takes the global value
// (*CONTROL_HOURGLASS, *CONTROL_BULK_VISCOSITY); QB and QW (shells) are not read.
struct Hourglass {
  Id id = 0;
  int ihq = 0;
  Real qm = 0.1;
  Real q1 = 0;
  Real q2 = 0;
  SourceLocation where;
};

// *CONTROL_HOURGLASS: the hourglass type and coefficient of parts without HGID.
struct ControlHourglass {
  int ihq = 0;
  Real qh = 0.1;
  SourceLocation where;
};

// *CONTROL_SPH, cards 1-3 (LS-DYNA defaults, except that a blank FORM reads as 1, not 0:
// Spall's default is the corrected formulation (FORM 1); see docs/KEYWORDS.md.
struct ControlSph {
  int ncbs = 1;        // steps between neighbour searches (Spall's Verlet list is adaptive)
  Id boxid = 0;
  Real dt = 1.0e20;    // SPH death time
  int idim = 3;        // 3: 3D, 2: plane strain, -2: axisymmetric
  int nmneigh = 150;   // LS-DYNA's neighbour memory per particle (Spall sizes lists itself)
  int form = 1;
  Real start = 0;      // SPH start time
  Real maxv = 1.0e15;  // particles faster than this are deactivated in LS-DYNA
  int cont = 0, deriv = 0, ini = 0, ishow = 0, ierod = 0, icont = 0, iavis = 0, isymp = 100;
  int ithk = 0, istab = 0;
  Real ql = 0.01;
  int sphsort = 0, ishift = 0;
  SourceLocation where;
  std::array<SourceLocation, 3> card_where;  // cards 1-3, for messages about their fields
};

// *SPALL_SPH_ARTIFICIAL_STRESS (a Spall keyword): Monaghan's (2000) artificial stress against the
// tensile instability, with Gray, Monaghan & Swift's (2001) defaults. Present = switched on.
// *SPALL_SPH_COLOUR_FIELD (a Spall keyword; seed 000 §4): colour-field categorization of SPH
// particles into surface, inner layers and interior, and optionally the treatment that lets
// surface and inner-layer particles pass only their hydrostatic stress to others. One card per
// part (PID 0: every SPH part).
struct SphColourField {
  Id pid = 0;
  int treat = 0;                  // 0 categorize only, 1 categorize and treat
  Real neighbour_fraction = 0.8;  // surface: fewer neighbours than this fraction of a full support
  Real normal_threshold = 0.3;    // ... and |n| h above this
  int layers = 1;                 // inner layers behind the surface
  int interval = 1;               // steps between categorizations
  int form = 1;                   // TFORM 1: relaxed exported deviator, 2: seed 000 literal (-pI)
  Real relaxation = 100;          // TAU: relaxation time of the exported deviator, in h / c
  SourceLocation where;
};

// *SPALL_RESIDUAL_STRESS (a Spall keyword; seed 000): how residual stress is detected in SPH
// solids. Without it the report is still written at the end of the run, with these defaults.
struct SphResidualStress {
  Real yield_fraction = 0.5;  // FRAC: von Mises above this fraction of the static yield stress ...
  Real strain_rate = 0;       // RATE: ... while the effective strain rate is below this (0: 1 % of the largest)
  int at_output = 0;          // OUTPUT: 1 also at every field output
  SourceLocation where;
};

struct SphArtificialStress {
  Real epsilon = 0.3;  // fraction of the tensile principal stress
  Real exponent = 4;   // n in f_ab^n, f_ab = W(r_ab) / W(initial spacing)
  SourceLocation where;
};

// *SPALL_SPH_TIMESTEP (a Spall keyword): the SPH solid's stable-step rule. RULE 0 (default):
// h / (c max(1, ||B||) + |v|), B the gradient correction; 1: LS-DYNA's h / (c + |v|).
struct SphTimestep {
  int rule = 0;
  SourceLocation where;
};

// A keyword Spall does not support: reported once as a warning. For sections, materials, EOS and
// *DEFINE_TABLE `id` is the ID on its first card (for *PART_ variants such as *PART_INERTIA, the
// PID), so that
// a reference to it can be refused by name.
struct UnsupportedKeyword {
  std::string keyword;
  Id id = 0;
  SourceLocation where;
};

// Which of the deck's *NODE and *ELEMENT_SPH cards a rank keeps (those *DEFINE_SPH_MESH_BOX generates
// among them, after the deck's own). Under MPI every rank reads every line, so that a card's syntax
// and ranges fail alike everywhere, but a deck of SPH fluid or solid alone need not be whole on any rank
// (docs/SCALING.md §5 step 4 f1): the cards are dealt in chunks of 4 096 in the deck's order, chunk
// c to rank c mod ranks, each card known by its ordinal (its place among the deck's cards of its
// keyword). One process, and every deck that is set up whole, keeps every card (ranks 1).
struct CardShare {
  static constexpr Index chunk = 4096;
  int rank = 0;
  int ranks = 1;

  bool whole() const { return ranks == 1; }
  bool holds(Index ordinal) const { return (ordinal / chunk) % ranks == rank; }
  // The ordinal of the card rank `of` holds at `held` among its cards (this rank's by default).
  Index ordinal(Index held, int of) const { return ((held / chunk) * ranks + of) * chunk + held % chunk; }
  Index ordinal(Index held) const { return ordinal(held, rank); }
};

struct Model {
  std::string title;
  std::vector<std::string> files;  // every file read, the top deck first

  // The *NODE and *ELEMENT_SPH cards this rank holds (every card unless `cards` deals them), and
  // how many the deck has in all.
  CardShare cards;
  Index node_cards = 0, sph_cards = 0;
  Id largest_node_id = 0;  // of every *NODE card (0 without)
  Index node_card_count() const { return cards.whole() ? static_cast<Index>(nodes.size()) : node_cards; }
  Index sph_card_count() const { return cards.whole() ? static_cast<Index>(sph_elements.size()) : sph_cards; }
  // Every rank's cards in, so that each holds every card (collective; nothing when whole).
  void gather_cards();
  // A card's file and line as every rank names them, for a card sent to another rank: its file's
  // place in `files` (a FileName's number is this process's own).
  struct CardLine {
    std::int32_t file = -1;
    std::int32_t line = 0;
  };
  CardLine card_line(const SourceLocation& where) const;
  SourceLocation location(CardLine line) const;

  std::vector<Node> nodes;
  std::vector<Part> parts;
  std::map<Id, Section> sections;
  std::map<Id, Material> materials;
  std::map<Id, ThermalMaterial> thermal_materials;
  std::map<Id, CoordinateSystem> coordinate_systems;
  std::map<Id, Vector> vectors;
  std::map<Id, Eos> eos;
  std::vector<ElementSph> sph_elements;
  std::vector<ElementSolid> solid_elements;
  std::vector<ElementShell> shell_elements;  // rigid parts only (validate)
  std::vector<SphMeshBox> sph_mesh_boxes;  // as read; their particles are in nodes/sph_elements
  std::map<Id, NodeSet> node_sets;
  std::map<Id, PartSet> part_sets;
  std::map<Id, SolidSet> solid_sets;
  std::map<Id, SegmentSet> segment_sets;
  std::map<Id, Curve> curves;

  std::vector<Spc> spcs;
  std::vector<PrescribedMotion> prescribed_motions;
  std::vector<InitialVelocity> initial_velocities;
  std::vector<InitialVelocityNode> initial_velocity_nodes;
  std::vector<InitialVelocityGeneration> initial_velocity_generations;
  std::vector<BodyLoad> body_loads;
  std::vector<RigidWallPlanar> rigid_walls;
  std::vector<ConstrainedRigidBodies> merged_rigid_bodies;
  std::vector<Contact> contacts;
  std::optional<ControlContact> control_contact;
  std::vector<RcforcMoment> rcforc_moments;

  std::optional<ControlTermination> termination;
  ControlTimestep timestep;
  ControlBulkViscosity bulk_viscosity;
  std::map<Id, Hourglass> hourglasses;
  std::map<Id, MatAddErosion> add_erosions;  // by MID
  std::optional<ControlHourglass> control_hourglass;
  std::optional<ControlSph> control_sph;
  std::optional<SphArtificialStress> sph_artificial_stress;
  std::optional<SphTimestep> sph_timestep;
  std::vector<SphColourField> sph_colour_fields;
  std::optional<SphResidualStress> sph_residual_stress;
  std::optional<OutputInterval> d3plot;
  std::optional<OutputInterval> glstat;
  std::optional<OutputInterval> rwforc;
  std::optional<OutputInterval> rcforc;
  std::optional<OutputInterval> rbdout;
  std::optional<OutputInterval> nodout;
  std::optional<OutputInterval> spcforc;
  std::optional<OutputInterval> bndout;
  std::optional<OutputInterval> matsum;
  std::vector<HistoryIds> history_nodes;  // in the deck's order
  std::optional<OutputInterval> elout;
  std::vector<HistoryIds> history_solids;  // in the deck's order
  std::optional<RestartOutput> runrsf;
  std::optional<DampingGlobal> damping_global;

  std::vector<UnsupportedKeyword> unsupported;

  // Frees the nodes, elements and node sets once the solver has built its stores from them: a run
  // keeps the curves and controls it refers to, not a second copy of the mesh (at a million
  // particles the mesh is most of the set-up's memory).
  void release_mesh();

  // The node IDs that cards other than *NODE and the elements name (node and segment sets,
  // constraints, prescribed motions, initial velocities, history nodes), ascending, each once.
  std::vector<Id> named_nodes() const;

  const Part* find_part(Id id) const;
  // The part's *MAT_RIGID card, or nullptr: such a part is a rigid body whatever its section.
  const MatRigid* rigid_material(const Part& part) const;
  // The thickness at a shell element's four corners: its THICn where given, else its section's Tn.
  // The element's part must have a *SECTION_SHELL (validate() checks it).
  std::array<Real, 4> shell_thickness(const ElementShell& element) const;
  // The axes of the coordinate system `cid` (the columns: local x, y, z in global coordinates; the
  // identity for 0), for a card of `keyword` whose `field` names it; an InputError at `where` when it
  // is not defined or its vectors give no axes.
  Mat3 axes(Id cid, const SourceLocation& where, const std::string& keyword, const std::string& field) const;
  // For a card of `keyword` whose `field` names the coordinate system `cid`: nothing when cid is 0
  // or a system with the global axes; otherwise an InputError at `where`, saying whether the system
  // is undefined, turned, or (with `initial_only` false) turning with its nodes during the run.
  void require_global_axes(Id cid, const SourceLocation& where, const std::string& keyword, const std::string& field,
                           bool initial_only) const;
};

}  // namespace spall::model
