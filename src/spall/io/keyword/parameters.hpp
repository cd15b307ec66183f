#pragma once
// *PARAMETER values and their scoping across *INCLUDE files, and *PARAMETER_EXPRESSION
// arithmetic.
//
// Scoping, as LS-DYNA documents it and pydyna's expand_parameters tests expect:
//  - *PARAMETER defines a global parameter, visible from its definition on in every file read
//    afterwards (an including file, a sibling include). Redefining one replaces its value: the
//    last definition read wins.
//  - *PARAMETER_LOCAL is visible only in the file that defines it and in files that file
//    includes; it shadows a global of the same name there and is forgotten at the file's end.
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace spall::io::keyword {

struct ParameterValue {
  char type = 'R';  // R real, I integer, C character
  double number = 0;
  std::string text;  // the value of a C parameter
};

class Parameters {
 public:
  Parameters() { local_.emplace_back(); }

  // Bracket the reading of one file: its local parameters live between the two calls.
  void enter_file() { local_.emplace_back(); }
  void leave_file() { local_.pop_back(); }

  void define(std::string_view name, ParameterValue value, bool local);
  // Names are case-insensitive. nullptr when not defined or not visible here.
  const ParameterValue* find(std::string_view name) const;

  // The value of an arithmetic expression over numbers, `pi` and visible parameters (by name, with
  // or without `&`): + - * / ** (also ^), parentheses, and the functions of the LS-DYNA manual's
  // *PARAMETER_EXPRESSION: sin cos tan csc sec ctn asin acos atan atan2 sinh cosh tanh asinh acosh
  // atanh min max sqrt mod abs sign int aint nint anint float exp log log10. Nothing, with `error`
  // set, if the expression cannot be evaluated.
  std::optional<double> evaluate(std::string_view expression, std::string& error) const;

 private:
  using Scope = std::unordered_map<std::string, ParameterValue>;
  static std::string key(std::string_view name);

  Scope global_;
  std::vector<Scope> local_;  // one per file being read, the innermost last
};

}  // namespace spall::io::keyword
