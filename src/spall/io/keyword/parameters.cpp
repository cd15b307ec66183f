#include "spall/io/keyword/parameters.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace spall::io::keyword {

std::string Parameters::key(std::string_view name) {
  std::string lowered(name);
  for (char& c : lowered) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lowered;
}

void Parameters::define(std::string_view name, ParameterValue value, bool local) {
  Scope& scope = local ? local_.back() : global_;
  scope[key(name)] = std::move(value);
}

const ParameterValue* Parameters::find(std::string_view name) const {
  const std::string k = key(name);
  for (auto scope = local_.rbegin(); scope != local_.rend(); ++scope)
    if (auto it = scope->find(k); it != scope->end()) return &it->second;
  if (auto it = global_.find(k); it != global_.end()) return &it->second;
  return nullptr;
}

namespace {

// Recursive descent over the grammar
//   sum     = product { ("+" | "-") product }
//   product = unary { ("*" | "/") unary }
//   unary   = ("-" | "+") unary | power
//   power   = primary [ ("**" | "^") unary ]      (right-associative, binds tighter than unary -)
//   primary = number | name [ "(" sum { "," sum } ")" ] | "(" sum ")"
class ExpressionParser {
 public:
  ExpressionParser(std::string_view text, const Parameters& parameters, std::string& error)
      : text_(text), parameters_(parameters), error_(error) {}

  std::optional<double> parse() {
    const double value = sum();
    skip_blanks();
    if (error_.empty() && position_ != text_.size())
      fail("unexpected '" + std::string(text_.substr(position_)) + "'");
    // A parameter is a field's value, and no field takes an infinity or NaN (1/0, 10**400, log(0)).
    if (error_.empty() && !std::isfinite(value)) fail("the value is not finite (" + std::to_string(value) + ")");
    if (!error_.empty()) return std::nullopt;
    return value;
  }

 private:
  void fail(std::string message) {
    if (error_.empty()) error_ = std::move(message);
  }
  void skip_blanks() {
    while (position_ < text_.size() && (text_[position_] == ' ' || text_[position_] == '\t'))
      ++position_;
  }
  bool accept(std::string_view token) {
    skip_blanks();
    if (text_.substr(position_, token.size()) != token) return false;
    position_ += token.size();
    return true;
  }

  double sum() {
    double value = product();
    while (error_.empty()) {
      if (accept("+")) value += product();
      else if (accept("-")) value -= product();
      else break;
    }
    return value;
  }
  double product() {
    double value = unary();
    while (error_.empty()) {
      if (accept("*")) value *= unary();
      else if (accept("/")) value /= unary();
      else break;
    }
    return value;
  }
  // Every recursion of the grammar passes here (a parenthesis, a sign, a power, an argument), so
  // this bounds the stack a deeply nested expression takes.
  double unary() {
    if (depth_ == deepest_nesting) {
      fail("nests deeper than " + std::to_string(deepest_nesting) + " levels (parentheses, signs, powers)");
      return 0;
    }
    ++depth_;
    const double value = accept("-") ? -unary() : accept("+") ? unary() : power();
    --depth_;
    return value;
  }
  double power() {
    const double base = primary();
    if (accept("**") || accept("^")) return std::pow(base, unary());
    return base;
  }
  double primary() {
    skip_blanks();
    if (position_ >= text_.size()) {
      fail("expression ends too early");
      return 0;
    }
    if (accept("(")) {
      const double value = sum();
      if (!accept(")")) fail("missing ')'");
      return value;
    }
    const char c = text_[position_];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return number();
    if (c == '&') ++position_;
    if (position_ < text_.size() && (std::isalpha(static_cast<unsigned char>(text_[position_])) ||
                                     text_[position_] == '_'))
      return name_or_call();
    fail("unexpected '" + std::string(text_.substr(position_)) + "'");
    return 0;
  }
  double number() {
    double value = 0;
    auto [end, error] = std::from_chars(text_.data() + position_, text_.data() + text_.size(), value);
    if (error != std::errc{}) {
      fail("bad number at '" + std::string(text_.substr(position_)) + "'");
      return 0;
    }
    position_ = static_cast<std::size_t>(end - text_.data());
    return value;
  }
  double name_or_call() {
    const std::size_t start = position_;
    while (position_ < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[position_])) ||
                                        text_[position_] == '_'))
      ++position_;
    const std::string_view name = text_.substr(start, position_ - start);
    if (!accept("(")) {
      const ParameterValue* value = parameters_.find(name);
      // The manual's one named constant; a parameter of the same name shadows it.
      if (!value && lowered(name) == "pi") return std::numbers::pi;
      if (!value) fail("parameter '" + std::string(name) + "' is not defined");
      else if (value->type == 'C') fail("parameter '" + std::string(name) + "' is not a number");
      return value ? value->number : 0;
    }
    std::vector<double> arguments;
    do {
      arguments.push_back(sum());
    } while (error_.empty() && accept(","));
    if (!accept(")")) fail("missing ')' after the arguments of " + std::string(name));
    if (!error_.empty()) return 0;
    return call(name, arguments);
  }
  static std::string lowered(std::string_view name) {
    std::string text(name);
    for (char& ch : text) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return text;
  }
  // The functions of the LS-DYNA manual's *PARAMETER_EXPRESSION, as in Fortran: MIN and MAX take
  // two or more arguments, SIGN(a, b) is |a| with the sign of b, MOD(a, p) has the sign of a.
  double call(std::string_view name, const std::vector<double>& a) {
    const std::string function = lowered(name);
    const std::size_t count = a.size();
    const auto one = [&](double (*f)(double)) {
      if (count != 1) fail(function + " takes one argument");
      return f(a[0]);
    };
    const auto two = [&](double (*f)(double, double)) {
      if (count != 2) fail(function + " takes two arguments");
      return count == 2 ? f(a[0], a[1]) : 0.0;
    };
    const auto extreme = [&](double (*f)(double, double)) {
      if (count < 2) fail(function + " takes two or more arguments");
      double value = a[0];
      for (std::size_t i = 1; i < count; ++i) value = f(value, a[i]);
      return value;
    };
    if (function == "sqrt") return one([](double x) { return std::sqrt(x); });
    if (function == "exp") return one([](double x) { return std::exp(x); });
    if (function == "log") return one([](double x) { return std::log(x); });
    if (function == "log10") return one([](double x) { return std::log10(x); });
    if (function == "abs") return one([](double x) { return std::abs(x); });
    if (function == "sin") return one([](double x) { return std::sin(x); });
    if (function == "cos") return one([](double x) { return std::cos(x); });
    if (function == "tan") return one([](double x) { return std::tan(x); });
    if (function == "csc") return one([](double x) { return 1.0 / std::sin(x); });
    if (function == "sec") return one([](double x) { return 1.0 / std::cos(x); });
    if (function == "ctn") return one([](double x) { return 1.0 / std::tan(x); });
    if (function == "asin") return one([](double x) { return std::asin(x); });
    if (function == "acos") return one([](double x) { return std::acos(x); });
    if (function == "atan") return one([](double x) { return std::atan(x); });
    if (function == "sinh") return one([](double x) { return std::sinh(x); });
    if (function == "cosh") return one([](double x) { return std::cosh(x); });
    if (function == "tanh") return one([](double x) { return std::tanh(x); });
    if (function == "asinh") return one([](double x) { return std::asinh(x); });
    if (function == "acosh") return one([](double x) { return std::acosh(x); });
    if (function == "atanh") return one([](double x) { return std::atanh(x); });
    // INT and AINT truncate toward zero, NINT and ANINT round half away from zero (Fortran).
    if (function == "int" || function == "aint") return one([](double x) { return std::trunc(x); });
    if (function == "nint" || function == "anint") return one([](double x) { return std::round(x); });
    if (function == "float") return one([](double x) { return x; });
    if (function == "atan2") return two([](double y, double x) { return std::atan2(y, x); });
    if (function == "mod") return two([](double x, double y) { return std::fmod(x, y); });
    if (function == "sign") return two([](double x, double y) { return std::copysign(x, y); });
    if (function == "min") return extreme([](double x, double y) { return std::fmin(x, y); });
    if (function == "max") return extreme([](double x, double y) { return std::fmax(x, y); });
    fail("unknown function '" + std::string(name) + "'");
    return 0;
  }

  static constexpr int deepest_nesting = 256;

  std::string_view text_;
  const Parameters& parameters_;
  std::string& error_;
  std::size_t position_ = 0;
  int depth_ = 0;
};

}  // namespace

std::optional<double> Parameters::evaluate(std::string_view expression, std::string& error) const {
  error.clear();
  return ExpressionParser(expression, *this, error).parse();
}

}  // namespace spall::io::keyword
