#pragma once
// The fields written at an output time, gathered from every formulation by name (DESIGN, phase 9).
// A field two formulations both have (pressure, density, stress ...) is one field: each writes the
// entries of its own nodes. Entries of nodes no formulation wrote keep a fill value: NaN for a real
// field (ParaView leaves NaN out of colour ranges and shows it in its NaN colour) and -1 for an
// integer field. Cells (hexahedra, tetrahedra, and the quadrilaterals and triangles of rigid shells)
// come in blocks of one type, with fields of their own.
// A set may hold the node fields of a window of the nodes alone (under MPI in blocks, the nodes a
// rank computes, which are those of its piece it writes; another rank writes the others): indexed
// as whole arrays, holding the window's entries.
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::discretization {

// A field: `components` values per point or cell, entity-major (x0 y0 z0 x1 y1 z1 ...). Three
// components show in ParaView as a vector. component_names, when given (one per component), label
// the components, e.g. symmetric_tensor_components for a stress in Voigt order.
struct Field {
  std::string name;
  int components = 1;
  std::variant<std::vector<double>, std::vector<std::int64_t>> values;
  std::vector<std::string> component_names = {};
};

// Voigt order of a symmetric tensor's six components, as the solver stores stress and strain.
inline const std::vector<std::string> symmetric_tensor_components = {"xx", "yy", "zz",
                                                                     "xy", "yz", "zx"};

inline constexpr double real_fill = std::numeric_limits<double>::quiet_NaN();
inline constexpr std::int64_t integer_fill = -1;

// The cell shapes a block may hold, with VTK's cell type numbers and node order.
enum class CellShape : std::uint8_t { hexahedron = 12, tetrahedron = 10, quadrilateral = 9, triangle = 5 };
int nodes_per_cell(CellShape shape);

struct CellBlock {
  CellShape shape = CellShape::hexahedron;
  std::vector<Index> connectivity;  // nodes_per_cell node indices per cell, VTK's order
  std::vector<Field> fields;        // one entry (of `components` values) per cell of this block
  std::size_t cell_count() const { return connectivity.size() / nodes_per_cell(shape); }
};

// A node field's values as a formulation writes them: entry k is component k % components of node
// k / components, as in an array of every node. An entry outside the set's window is another
// rank's to write: a value given to it is let go.
template <typename T>
class NodeValues {
 public:
  NodeValues(std::span<T> values, std::size_t first_entry) : values_(values), first_(first_entry) {}
  T& operator[](std::size_t k) const { return k - first_ < values_.size() ? values_[k - first_] : elsewhere_; }
  std::size_t size() const { return values_.size(); }  // the window's entries

 private:
  std::span<T> values_;
  std::size_t first_;
  mutable T elsewhere_{};
};

class FieldSet {
 public:
  // Node fields of every node.
  explicit FieldSet(Index node_count) : FieldSet(0, node_count) {}
  // Node fields of the nodes [first, end) alone.
  FieldSet(Index first, Index end) : first_(first), node_count_(end - first) {}

  // The node field `name` with `components` values per node: created filled with real_fill on the
  // first request, the same field on the next. A request whose components or kind differ from the
  // field's throws std::logic_error (two formulations disagree on what the name means).
  NodeValues<double> node_real(std::string_view name, int components = 1,
                               const std::vector<std::string>& component_names = {});
  NodeValues<std::int64_t> node_integer(std::string_view name, int components = 1);
  // The nodes [first_node(), first_node() + node_count()) the node fields hold, in this order.
  Index first_node() const { return first_; }
  Index node_count() const { return node_count_; }

  const std::vector<Field>& node_fields() const { return node_fields_; }
  std::vector<Field>& node_fields() { return node_fields_; }

  // A new block of cells; its fields are the caller's to fill, one entry per cell.
  CellBlock& add_cell_block(CellShape shape);
  const std::vector<CellBlock>& cell_blocks() const { return cell_blocks_; }

 private:
  Field& node_field(std::string_view name, int components, bool integer,
                    const std::vector<std::string>& component_names);

  Index first_;
  Index node_count_;
  std::vector<Field> node_fields_;
  std::vector<CellBlock> cell_blocks_;
};

}  // namespace spall::discretization
