// Recursive-descent parser and tree evaluator for the expression language in expression.h.
#include "geometry/implicit/expression.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace surfaced::implicit {
namespace {

enum class Op { Const, X, Y, Z, Add, Sub, Mul, Div, Pow, Neg, Sqrt, Abs, Sin, Cos, Exp, Min, Max };

struct Node {
    Op op = Op::Const;
    double constant = 0;
    int a = -1, b = -1;  //!< children (indices into the node array)
    int depth = 1;       //!< height of the subtree
};

//! A value and its gradient (forward-mode differentiation).
struct Dual {
    double v = 0;
    Vec3 g;
};

class Parser {
public:
    Parser(std::string_view text, const ExpressionLimits& limits) : text_(text), limits_(limits) {}

    std::optional<GeoError> run(std::vector<Node>& nodes, int& root) {
        root = expr(0);
        if (root >= 0) {
            skip_space();
            if (pos_ < text_.size())
                fail(pos_, "unexpected '" + std::string(1, text_[pos_]) + "' after the expression");
        }
        if (error_) return error_;
        nodes = std::move(nodes_);
        return std::nullopt;
    }

private:
    int fail(std::size_t at, const std::string& what, ErrorCode code = ErrorCode::ParseError) {
        if (!error_)
            error_ =
                make_error(code, "at character " + std::to_string(at) + ": " + what, -1, static_cast<std::int64_t>(at));
        return -1;
    }

    void skip_space() {
        while (pos_ < text_.size() &&
               (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\n' || text_[pos_] == '\r'))
            ++pos_;
    }

    bool accept(char c) {
        skip_space();
        if (pos_ < text_.size() && text_[pos_] == c) {
            ++pos_;
            return true;
        }
        return false;
    }

    int add(Op op, std::size_t at, int a = -1, int b = -1, double constant = 0) {
        if (nodes_.size() >= limits_.max_nodes)
            return fail(at, "the expression has more than " + std::to_string(limits_.max_nodes) + " nodes",
                        ErrorCode::BudgetExceeded);
        Node n{op, constant, a, b, 1};
        if (a >= 0) n.depth = std::max(n.depth, nodes_[static_cast<std::size_t>(a)].depth + 1);
        if (b >= 0) n.depth = std::max(n.depth, nodes_[static_cast<std::size_t>(b)].depth + 1);
        if (n.depth > limits_.max_depth)
            return fail(at, "the expression is nested deeper than " + std::to_string(limits_.max_depth),
                        ErrorCode::BudgetExceeded);
        nodes_.push_back(n);
        return static_cast<int>(nodes_.size() - 1);
    }

    //! Guards the recursion itself (parentheses nest without adding nodes).
    bool too_deep(int depth) {
        if (depth <= limits_.max_depth) return false;
        fail(pos_, "the expression is nested deeper than " + std::to_string(limits_.max_depth),
             ErrorCode::BudgetExceeded);
        return true;
    }

    int expr(int depth) {
        if (too_deep(depth)) return -1;
        int left = term(depth);
        while (left >= 0) {
            skip_space();
            const std::size_t at = pos_;
            if (accept('+')) {
                const int right = term(depth);
                if (right < 0) return -1;
                left = add(Op::Add, at, left, right);
            } else if (accept('-')) {
                const int right = term(depth);
                if (right < 0) return -1;
                left = add(Op::Sub, at, left, right);
            } else {
                break;
            }
        }
        return left;
    }

    int term(int depth) {
        int left = unary(depth);
        while (left >= 0) {
            skip_space();
            const std::size_t at = pos_;
            if (accept('*')) {
                const int right = unary(depth);
                if (right < 0) return -1;
                left = add(Op::Mul, at, left, right);
            } else if (accept('/')) {
                const int right = unary(depth);
                if (right < 0) return -1;
                left = add(Op::Div, at, left, right);
            } else {
                break;
            }
        }
        return left;
    }

    int unary(int depth) {
        if (too_deep(depth)) return -1;
        skip_space();
        const std::size_t at = pos_;
        if (accept('-')) {
            const int operand = unary(depth + 1);
            return operand < 0 ? -1 : add(Op::Neg, at, operand);
        }
        return power(depth);
    }

    int power(int depth) {
        const int base = primary(depth);
        if (base < 0) return -1;
        skip_space();
        const std::size_t at = pos_;
        if (!accept('^')) return base;
        const int exponent = unary(depth + 1);
        return exponent < 0 ? -1 : add(Op::Pow, at, base, exponent);
    }

    int primary(int depth) {
        skip_space();
        const std::size_t at = pos_;
        if (pos_ >= text_.size()) return fail(at, "unexpected end of the expression, expected a value");
        const char c = text_[pos_];
        if ((c >= '0' && c <= '9') || c == '.') return number();
        if (c == '(') {
            ++pos_;
            const int inner = expr(depth + 1);
            if (inner < 0) return -1;
            if (!accept(')')) return fail(pos_, "expected ')'");
            return inner;
        }
        if (std::isalpha(static_cast<unsigned char>(c))) {
            std::size_t end = pos_;
            while (end < text_.size() && std::isalnum(static_cast<unsigned char>(text_[end]))) ++end;
            const std::string_view name = text_.substr(pos_, end - pos_);
            pos_ = end;
            if (name == "x") return add(Op::X, at);
            if (name == "y") return add(Op::Y, at);
            if (name == "z") return add(Op::Z, at);
            struct Fn {
                std::string_view name;
                Op op;
                int arity;
            };
            static constexpr Fn kFunctions[] = {{"sqrt", Op::Sqrt, 1}, {"abs", Op::Abs, 1}, {"sin", Op::Sin, 1},
                                                {"cos", Op::Cos, 1},   {"exp", Op::Exp, 1}, {"min", Op::Min, 2},
                                                {"max", Op::Max, 2}};
            for (const Fn& fn : kFunctions) {
                if (fn.name != name) continue;
                if (!accept('(')) return fail(pos_, "expected '(' after " + std::string(name));
                const int a = expr(depth + 1);
                if (a < 0) return -1;
                int b = -1;
                if (fn.arity == 2) {
                    if (!accept(',')) return fail(pos_, "expected ',' (" + std::string(name) + " takes two arguments)");
                    b = expr(depth + 1);
                    if (b < 0) return -1;
                }
                if (!accept(')')) return fail(pos_, "expected ')'");
                return add(fn.op, at, a, b);
            }
            return fail(at, "unknown name \"" + std::string(name) +
                                "\" (variables x, y, z; functions sqrt, abs, sin, cos, exp, min, max)");
        }
        return fail(at, "unexpected '" + std::string(1, c) + "', expected a number, x, y, z, a function or '('");
    }

    int number() {
        const std::size_t start = pos_;
        auto digits = [&] {
            const std::size_t from = pos_;
            while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') ++pos_;
            return pos_ > from;
        };
        bool any = digits();
        if (pos_ < text_.size() && text_[pos_] == '.') {
            ++pos_;
            any = digits() || any;
        }
        if (!any) return fail(start, "malformed number");
        if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
            ++pos_;
            if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
            if (!digits()) return fail(pos_, "malformed exponent");
        }
        double v = 0;
        const auto [ptr, ec] = std::from_chars(text_.data() + start, text_.data() + pos_, v);
        if (ec != std::errc() || ptr != text_.data() + pos_ || !std::isfinite(v))
            return fail(start, "number out of range");
        return add(Op::Const, start, -1, -1, v);
    }

    std::string_view text_;
    ExpressionLimits limits_;
    std::size_t pos_ = 0;
    std::vector<Node> nodes_;
    std::optional<GeoError> error_;
};

class Expression final : public Field {
public:
    Expression(std::vector<Node> nodes, int root) : nodes_(std::move(nodes)), root_(root) {
        double l = 1.0;
        for (int i = 0; i <= 8; ++i)
            for (int j = 0; j <= 8; ++j)
                for (int k = 0; k <= 8; ++k) {
                    const Vec3 p{-2 + 0.5 * i, -2 + 0.5 * j, -2 + 0.5 * k};
                    const double g = norm(eval(root_, p).g);
                    if (std::isfinite(g)) l = std::max(l, g);
                }
        lipschitz_ = l;
    }

    double value(const Vec3& p) const override { return value_at(root_, p); }
    Vec3 gradient(const Vec3& p) const override { return eval(root_, p).g; }
    FieldKind kind() const override { return FieldKind::General; }
    double lipschitz() const override { return lipschitz_; }

private:
    const Node& at(int i) const { return nodes_[static_cast<std::size_t>(i)]; }

    //! Value only (the common case: no gradient bookkeeping). Recursion depth <= max_depth.
    double value_at(int i, const Vec3& p) const {
        const Node& n = at(i);
        switch (n.op) {
            case Op::Const: return n.constant;
            case Op::X: return p.x;
            case Op::Y: return p.y;
            case Op::Z: return p.z;
            case Op::Add: return value_at(n.a, p) + value_at(n.b, p);
            case Op::Sub: return value_at(n.a, p) - value_at(n.b, p);
            case Op::Mul: return value_at(n.a, p) * value_at(n.b, p);
            case Op::Div: return value_at(n.a, p) / value_at(n.b, p);
            case Op::Pow: return std::pow(value_at(n.a, p), value_at(n.b, p));
            case Op::Neg: return -value_at(n.a, p);
            case Op::Sqrt: return std::sqrt(value_at(n.a, p));
            case Op::Abs: return std::abs(value_at(n.a, p));
            case Op::Sin: return std::sin(value_at(n.a, p));
            case Op::Cos: return std::cos(value_at(n.a, p));
            case Op::Exp: return std::exp(value_at(n.a, p));
            case Op::Min: return std::min(value_at(n.a, p), value_at(n.b, p));
            case Op::Max: return std::max(value_at(n.a, p), value_at(n.b, p));
        }
        return 0;
    }

    Dual eval(int i, const Vec3& p) const {
        const Node& n = at(i);
        switch (n.op) {
            case Op::Const: return {n.constant, {}};
            case Op::X: return {p.x, {1, 0, 0}};
            case Op::Y: return {p.y, {0, 1, 0}};
            case Op::Z: return {p.z, {0, 0, 1}};
            default: break;
        }
        const Dual a = eval(n.a, p);
        const Dual b = n.b >= 0 ? eval(n.b, p) : Dual{};
        switch (n.op) {
            case Op::Add: return {a.v + b.v, a.g + b.g};
            case Op::Sub: return {a.v - b.v, a.g - b.g};
            case Op::Mul: return {a.v * b.v, a.g * b.v + b.g * a.v};
            case Op::Div: return {a.v / b.v, (a.g * b.v - b.g * a.v) * (1.0 / (b.v * b.v))};
            case Op::Pow: {
                const double v = std::pow(a.v, b.v);
                Vec3 g;
                if (a.g != Vec3{}) g += a.g * (b.v == 0 ? 0.0 : b.v * std::pow(a.v, b.v - 1));
                if (b.g != Vec3{} && a.v > 0) g += b.g * (v * std::log(a.v));
                return {v, g};
            }
            case Op::Neg: return {-a.v, a.g * -1.0};
            case Op::Sqrt: {
                const double v = std::sqrt(a.v);
                return {v, v > 0 ? a.g * (0.5 / v) : Vec3{}};
            }
            case Op::Abs: return {std::abs(a.v), a.v < 0 ? a.g * -1.0 : a.g};
            case Op::Sin: return {std::sin(a.v), a.g * std::cos(a.v)};
            case Op::Cos: return {std::cos(a.v), a.g * -std::sin(a.v)};
            case Op::Exp: {
                const double v = std::exp(a.v);
                return {v, a.g * v};
            }
            case Op::Min: return a.v <= b.v ? a : b;
            case Op::Max: return a.v >= b.v ? a : b;
            default: break;
        }
        return {};
    }

    std::vector<Node> nodes_;
    int root_;
    double lipschitz_ = 1;
};

}  // namespace

Result<FieldPtr> parse_expression(std::string_view text, const ExpressionLimits& limits) {
    std::vector<Node> nodes;
    int root = -1;
    Parser parser(text, limits);
    if (auto error = parser.run(nodes, root)) return *error;
    return FieldPtr(std::make_shared<Expression>(std::move(nodes), root));
}

}  // namespace surfaced::implicit
