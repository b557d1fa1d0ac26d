// Algebraic surfaces f(x, y, z) = 0 from a small expression language, parsed into a tree and evaluated by walking
// it (never compiled or executed as code).
//
//   expr    := term (('+' | '-') term)*
//   term    := unary (('*' | '/') unary)*
//   unary   := '-' unary | power                    so -x^2 = -(x^2)
//   power   := primary ('^' unary)?                 right associative: x^2^3 = x^(2^3); 2^-1 allowed
//   primary := number | 'x' | 'y' | 'z' | '(' expr ')' | fn1 '(' expr ')' | fn2 '(' expr ',' expr ')'
//   fn1     := sqrt | abs | sin | cos | exp        fn2 := min | max
//   number  := digits ['.' digits] [('e'|'E') ['+'|'-'] digits]  (or '.' digits); whitespace between tokens.
//
// Limits: at most `max_nodes` tree nodes and tree (and parenthesis) depth at most `max_depth`; exceeding either is
// ErrorCode::BudgetExceeded, a syntax error ErrorCode::ParseError; both carry the 0-based character offset in
// GeoError::offset and name it in the message ("at character 7: expected ')'").
//
// The field is FieldKind::General: only the sign is meaningful. gradient() is exact (forward-mode differentiation
// of the tree; at kinks of abs/min/max one side's derivative, sqrt'(0) taken as 0). Where the expression is
// undefined (sqrt of a negative, 0/0) the value is NaN. lipschitz() is an *estimate*, not a bound: the largest
// |∇f| over a 9x9x9 grid on [-2, 2]^3 (at least 1). Ray casting therefore never trusts it: General fields are
// marched with fixed steps and a sign-change test (query.h).
#pragma once

#include <cstddef>
#include <string_view>

#include "geometry/core/result.h"
#include "geometry/implicit/primitives.h"

namespace surfaced::implicit {

struct ExpressionLimits {
    std::size_t max_nodes = 10'000;
    int max_depth = 64;
};

Result<FieldPtr> parse_expression(std::string_view text, const ExpressionLimits& limits = {});

}  // namespace surfaced::implicit
