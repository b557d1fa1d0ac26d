// SVG path data parser: a single-pass scanner over the bytes (no copies of the input, no recursion). Every error
// carries the byte offset of the offending token; work is bounded by max_commands / max_pieces before pieces are
// appended.
#include "geometry/curves/svg_path.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <numbers>
#include <optional>
#include <string>
#include <system_error>

namespace surfaced {
namespace {

bool is_wsp(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool starts_number(char c) { return is_digit(c) || c == '+' || c == '-' || c == '.'; }

//! Number of coordinates each command takes per repetition.
int arity(char command) {
    switch (command) {
        case 'M':
        case 'm':
        case 'L':
        case 'l':
        case 'T':
        case 't': return 2;
        case 'H':
        case 'h':
        case 'V':
        case 'v': return 1;
        case 'C':
        case 'c': return 6;
        case 'S':
        case 's':
        case 'Q':
        case 'q': return 4;
        case 'A':
        case 'a': return 7;
        case 'Z':
        case 'z': return 0;
        default: return -1;
    }
}

//! Printable form of a token for messages: ASCII as is, other bytes as \xNN (the message must stay valid UTF-8
//! whatever the input), at most 16 bytes of it.
std::string describe_token(std::string_view data, std::size_t at) {
    if (at >= data.size()) return "the end of the data";
    std::string out = "'";
    std::size_t end = at;
    if (data[at] == ',')
        end = at + 1;  // a lone separator
    else
        while (end < data.size() && end - at < 16 && (end == at || (!is_wsp(data[end]) && data[end] != ','))) ++end;
    for (std::size_t i = at; i < end; ++i) {
        const unsigned char c = static_cast<unsigned char>(data[i]);
        if (c >= 0x20 && c < 0x7f && c != '\'' && c != '\\') {
            out += static_cast<char>(c);
        } else {
            char buffer[8];
            std::snprintf(buffer, sizeof buffer, "\\x%02X", c);
            out += buffer;
        }
    }
    if (end < data.size() && end - at >= 16 && !is_wsp(data[end]) && data[end] != ',') out += "...";
    return out + "'";
}

BezierCurve line(const Vec3& a, const Vec3& b) {
    BezierCurve c;
    c.points = {a, b};
    return c;
}

enum class Previous { Other, Cubic, Quadratic };

class Parser {
public:
    Parser(std::string_view data, const SvgPathOptions& options) : data_(data), options_(options) {}

    Result<std::vector<BezierChain>> run() {
        skip_wsp();
        if (pos_ >= data_.size()) return std::move(chains_);
        if (data_[pos_] != 'M' && data_[pos_] != 'm')
            return fail(pos_, "path data must start with 'M' or 'm', found " + describe_token(data_, pos_));
        while (true) {
            skip_wsp();
            if (pos_ >= data_.size()) break;
            const std::size_t at = pos_;
            const char command = data_[pos_];
            if (arity(command) < 0) {
                if (starts_number(command))
                    return fail(at, "expected a command letter after '" + std::string(1, last_command_) + "', found " +
                                        describe_token(data_, at));
                return fail(at, "unknown command " + describe_token(data_, at));
            }
            if ((command == 'A' || command == 'a') && options_.arcs == SvgArcConversion::Reject)
                return fail(at, "arcs are not accepted, found " + describe_token(data_, at));
            ++pos_;
            last_command_ = command;
            if (command == 'Z' || command == 'z') {
                if (auto e = count_command(at)) return *e;
                close_path();
                continue;
            }
            // the first repetition is mandatory, further ones are implicit while numbers follow
            char repeated = command;
            bool first = true;
            while (true) {
                if (!first) {
                    const std::size_t before = pos_;
                    skip_wsp();
                    bool comma = false;
                    if (pos_ < data_.size() && data_[pos_] == ',') {
                        comma = true;
                        ++pos_;
                        skip_wsp();
                    }
                    if (pos_ >= data_.size() || !starts_number(data_[pos_])) {
                        if (comma)
                            return fail(pos_, "expected a number after ',' (another '" + std::string(1, repeated) +
                                                  "'), found " + describe_token(data_, pos_));
                        pos_ = before;
                        break;
                    }
                }
                if (auto e = count_command(pos_)) return *e;
                if (auto e = one_command(repeated, first)) return *e;
                first = false;
                if (repeated == 'M') repeated = 'L';
                if (repeated == 'm') repeated = 'l';
            }
        }
        finish_chain();
        return std::move(chains_);
    }

private:
    GeoError fail(std::size_t at, const std::string& what, ErrorCode code = ErrorCode::ParseError) const {
        return make_error(code, "svg path: offset " + std::to_string(at) + ": " + what, -1,
                          static_cast<std::int64_t>(at));
    }

    void skip_wsp() {
        while (pos_ < data_.size() && is_wsp(data_[pos_])) ++pos_;
    }

    //! Separator before a number or flag that is not the first of its command: wsp* (',' wsp*)?.
    void skip_separator() {
        skip_wsp();
        if (pos_ < data_.size() && data_[pos_] == ',') {
            ++pos_;
            skip_wsp();
        }
    }

    std::optional<GeoError> count_command(std::size_t at) {
        if (++commands_ > options_.max_commands)
            return fail(at, "more than " + std::to_string(options_.max_commands) + " commands",
                        ErrorCode::BudgetExceeded);
        return std::nullopt;
    }

    std::optional<GeoError> reserve_pieces(std::size_t at, double count) {
        if (count > static_cast<double>(options_.max_pieces - pieces_))
            return fail(at, "more than " + std::to_string(options_.max_pieces) + " curve pieces",
                        ErrorCode::BudgetExceeded);
        return std::nullopt;
    }

    //! One number: sign? (digits ('.' digits?)? | '.' digits) (('e'|'E') sign? digits)?
    std::optional<GeoError> number(char command, bool first_of_command, double& out) {
        if (first_of_command)
            skip_wsp();
        else
            skip_separator();
        const std::size_t start = pos_;
        std::size_t p = pos_;
        if (p < data_.size() && (data_[p] == '+' || data_[p] == '-')) ++p;
        const std::size_t mantissa = p;
        std::size_t digits = 0;
        while (p < data_.size() && is_digit(data_[p])) ++p, ++digits;
        if (p < data_.size() && data_[p] == '.') {
            ++p;
            while (p < data_.size() && is_digit(data_[p])) ++p, ++digits;
        }
        if (digits == 0)
            return fail(start, "expected a number after '" + std::string(1, command) + "', found " +
                                   describe_token(data_, start));
        bool negative_exponent = false;
        if (p < data_.size() && (data_[p] == 'e' || data_[p] == 'E')) {
            std::size_t q = p + 1;
            if (q < data_.size() && (data_[q] == '+' || data_[q] == '-')) {
                negative_exponent = data_[q] == '-';
                ++q;
            }
            if (q < data_.size() && is_digit(data_[q])) {
                while (q < data_.size() && is_digit(data_[q])) ++q;
                p = q;
            } else {
                negative_exponent = false;  // not an exponent: the 'e' is left for the command scanner
            }
        }
        double value = 0;
        const char* first = data_.data() + mantissa;
        const char* last = data_.data() + p;
        const auto [ptr, ec] = std::from_chars(first, last, value);
        if (ec == std::errc::result_out_of_range && negative_exponent) {
            value = 0;  // underflow: smaller than the smallest double
        } else if (ec != std::errc() || ptr != last || !std::isfinite(value)) {
            return fail(start, "number " + describe_token(data_, start) + " is out of range");
        }
        out = data_[start] == '-' ? -value : value;
        pos_ = p;
        return std::nullopt;
    }

    std::optional<GeoError> flag(char command, bool& out) {
        skip_separator();
        if (pos_ < data_.size() && (data_[pos_] == '0' || data_[pos_] == '1')) {
            out = data_[pos_] == '1';
            ++pos_;
            return std::nullopt;
        }
        return fail(pos_, "expected a flag (0 or 1) after '" + std::string(1, command) + "', found " +
                              describe_token(data_, pos_));
    }

    void finish_chain() {
        if (!chain_.pieces.empty()) chains_.push_back(std::move(chain_));
        chain_ = BezierChain{};
    }

    void add(BezierCurve piece) {
        ++pieces_;
        chain_.pieces.push_back(std::move(piece));
    }

    std::optional<GeoError> check_finite(std::size_t at, std::initializer_list<Vec3> points) const {
        for (const Vec3& p : points)
            if (!is_finite(p)) return fail(at, "coordinates overflow to infinity");
        return std::nullopt;
    }

    void close_path() {
        if (current_ != start_ && !chain_.pieces.empty()) add(line(current_, start_));
        chain_.closed = true;
        finish_chain();
        current_ = start_;
        previous_ = Previous::Other;
    }

    // One case per SVG path command (M L H V C S Q T A Z, absolute and relative): kept whole so that the grammar
    // reads as the specification's table does.
    std::optional<GeoError> one_command(char command, bool first) {
        const std::size_t at = pos_;
        const bool relative = command >= 'a' && command <= 'z';
        const Vec3 origin = relative ? current_ : Vec3{};
        const int count = arity(command);
        double v[7] = {0, 0, 0, 0, 0, 0, 0};
        bool large_arc = false, sweep = false;
        for (int i = 0; i < count; ++i) {
            if (command == 'A' || command == 'a') {
                if (i == 3) {
                    if (auto e = flag(command, large_arc)) return e;
                    continue;
                }
                if (i == 4) {
                    if (auto e = flag(command, sweep)) return e;
                    continue;
                }
            }
            if (auto e = number(command, first && i == 0, v[i])) return e;
        }
        const auto point = [&](int i) { return Vec3{origin.x + v[i], origin.y + v[i + 1], 0.0}; };
        Previous next = Previous::Other;
        switch (command) {
            case 'M':
            case 'm': {
                const Vec3 p = point(0);
                if (auto e = check_finite(at, {p})) return e;
                finish_chain();
                start_ = current_ = p;
                break;
            }
            case 'L':
            case 'l':
            case 'H':
            case 'h':
            case 'V':
            case 'v': {
                Vec3 p = current_;
                if (command == 'L' || command == 'l') p = point(0);
                if (command == 'H') p.x = v[0];
                if (command == 'h') p.x = current_.x + v[0];
                if (command == 'V') p.y = v[0];
                if (command == 'v') p.y = current_.y + v[0];
                if (auto e = check_finite(at, {p})) return e;
                if (auto e = reserve_pieces(at, 1)) return e;
                add(line(current_, p));
                current_ = p;
                break;
            }
            case 'C':
            case 'c':
            case 'S':
            case 's': {
                Vec3 c1, c2, p;
                if (command == 'C' || command == 'c') {
                    c1 = point(0), c2 = point(2), p = point(4);
                } else {
                    c1 = previous_ == Previous::Cubic ? 2.0 * current_ - control_ : current_;
                    c2 = point(0), p = point(2);
                }
                if (auto e = check_finite(at, {c1, c2, p})) return e;
                if (auto e = reserve_pieces(at, 1)) return e;
                BezierCurve curve;
                curve.points = {current_, c1, c2, p};
                add(std::move(curve));
                control_ = c2;
                current_ = p;
                next = Previous::Cubic;
                break;
            }
            case 'Q':
            case 'q':
            case 'T':
            case 't': {
                Vec3 c1, p;
                if (command == 'Q' || command == 'q') {
                    c1 = point(0), p = point(2);
                } else {
                    c1 = previous_ == Previous::Quadratic ? 2.0 * current_ - control_ : current_;
                    p = point(0);
                }
                if (auto e = check_finite(at, {c1, p})) return e;
                if (auto e = reserve_pieces(at, 1)) return e;
                BezierCurve curve;
                curve.points = {current_, c1, p};
                add(std::move(curve));
                control_ = c1;
                current_ = p;
                next = Previous::Quadratic;
                break;
            }
            case 'A':
            case 'a': {
                const Vec3 p = point(5);
                if (auto e = check_finite(at, {p})) return e;
                if (auto e = arc(at, v[0], v[1], v[2], large_arc, sweep, p)) return e;
                current_ = p;
                break;
            }
            default: break;
        }
        previous_ = next;
        return std::nullopt;
    }

    //! SVG 1.1 F.6.5 endpoint to centre conversion, with the radii normalised away (no overflow of rx^2 ry^2), then
    //! pieces of at most 90 degrees.
    std::optional<GeoError> arc(std::size_t at, double rx, double ry, double rotation_deg, bool large_arc, bool sweep,
                                const Vec3& end) {
        const Vec3 begin = current_;
        if (begin == end) return std::nullopt;  // F.6.2: the arc is omitted
        rx = std::abs(rx);
        ry = std::abs(ry);
        if (rx == 0 || ry == 0) {
            if (auto e = reserve_pieces(at, 1)) return e;
            add(line(begin, end));
            return std::nullopt;
        }
        const double phi = std::fmod(rotation_deg, 360.0) * std::numbers::pi / 180.0;
        const double cphi = std::cos(phi), sphi = std::sin(phi);
        // F.6.5.1, divided by the radii: (a, b) = (x1', y1') / (rx, ry)
        const double hx = 0.5 * (begin.x - end.x), hy = 0.5 * (begin.y - end.y);
        double a = (cphi * hx + sphi * hy) / rx;
        double b = (-sphi * hx + cphi * hy) / ry;
        const double lambda = a * a + b * b;
        double coef = 0;
        if (lambda == 0) {  // the chord is negligible against the radii (underflow): the arc is a straight line
            if (auto e = reserve_pieces(at, 1)) return e;
            add(line(begin, end));
            return std::nullopt;
        }
        if (!std::isfinite(lambda)) return fail(at, "arc parameters are out of range");
        if (lambda > 1) {  // F.6.6: radii too small, scale them up; the centre is then the chord's midpoint
            const double s = std::sqrt(lambda);
            rx *= s;
            ry *= s;
            a /= s;
            b /= s;
        } else {
            coef = std::sqrt(std::max(0.0, (1 - lambda) / lambda));
            if (large_arc == sweep) coef = -coef;
        }
        // centre in the normalised frame: (cx', cy') / (rx, ry) = coef (b, -a)
        const double ncx = coef * b, ncy = -coef * a;
        const double cxp = ncx * rx, cyp = ncy * ry;
        const Vec3 centre{cphi * cxp - sphi * cyp + 0.5 * (begin.x + end.x),
                          sphi * cxp + cphi * cyp + 0.5 * (begin.y + end.y), 0.0};
        const double ux = a - ncx, uy = b - ncy, vx = -a - ncx, vy = -b - ncy;
        const double theta1 = std::atan2(uy, ux);
        double delta = std::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
        if (!sweep && delta > 0) delta -= 2 * std::numbers::pi;
        if (sweep && delta < 0) delta += 2 * std::numbers::pi;
        if (!std::isfinite(delta) || delta == 0 || !is_finite(centre) || !std::isfinite(rx) || !std::isfinite(ry))
            return fail(at, "arc parameters are out of range");

        // the ellipse point at angle theta (unit circle point (c, s) mapped by centre + R(phi) diag(rx, ry))
        const auto map = [&](double x, double y) {
            return Vec3{centre.x + cphi * rx * x - sphi * ry * y, centre.y + sphi * rx * x + cphi * ry * y, 0.0};
        };
        std::size_t k = static_cast<std::size_t>(std::ceil(std::abs(delta) / (std::numbers::pi / 2) - 1e-12));
        k = std::max<std::size_t>(k, 1);
        const bool cubic = options_.arcs == SvgArcConversion::Cubic;
        if (cubic) {
            // error of the k = 4/3 tan(d/4) cubic on the unit circle is at most (4/27) sin^6(d/4) / cos^2(d/4)
            // (twice the true maximum); the map stretches distances by at most max(rx, ry)
            const double radius = std::max(rx, ry);
            const auto bound = [&](double d) {
                const double s = std::sin(d / 4), c = std::cos(d / 4);
                return 4.0 / 27.0 * s * s * s * s * s * s / (c * c) * radius;
            };
            const double x = std::pow(27.0 * options_.arc_tolerance / (4.0 * radius), 1.0 / 6.0);
            const double estimate = std::ceil(std::abs(delta) / (4 * x));
            if (auto e = reserve_pieces(at, std::max(estimate, static_cast<double>(k)))) return e;
            k = std::max(k, static_cast<std::size_t>(estimate));
            while (bound(std::abs(delta) / static_cast<double>(k)) > options_.arc_tolerance) {
                ++k;
                if (auto e = reserve_pieces(at, static_cast<double>(k))) return e;
            }
        } else {
            if (auto e = reserve_pieces(at, static_cast<double>(k))) return e;
        }
        const double step = delta / static_cast<double>(k);
        Vec3 from = begin;
        for (std::size_t i = 0; i < k; ++i) {
            const double t0 = theta1 + step * static_cast<double>(i);
            const double t1 = i + 1 == k ? theta1 + delta : theta1 + step * static_cast<double>(i + 1);
            const Vec3 to = i + 1 == k ? end : map(std::cos(t1), std::sin(t1));
            BezierCurve piece;
            if (cubic) {
                const double h = 4.0 / 3.0 * std::tan(step / 4);
                const double c0 = std::cos(t0), s0 = std::sin(t0), c1 = std::cos(t1), s1 = std::sin(t1);
                piece.points = {from, map(c0 - h * s0, s0 + h * c0), map(c1 + h * s1, s1 - h * c1), to};
            } else {
                const double half = 0.5 * step, w = std::cos(half), tm = t0 + half;
                piece.points = {from, map(std::cos(tm) / w, std::sin(tm) / w), to};
                piece.weights = {1.0, w, 1.0};
            }
            for (const Vec3& q : piece.points)
                if (!is_finite(q)) return fail(at, "arc parameters are out of range");
            add(std::move(piece));
            from = to;
        }
        return std::nullopt;
    }

    std::string_view data_;
    const SvgPathOptions& options_;
    std::size_t pos_ = 0;
    std::vector<BezierChain> chains_;
    BezierChain chain_;
    Vec3 start_, current_, control_;
    Previous previous_ = Previous::Other;
    char last_command_ = 'M';
    std::size_t commands_ = 0, pieces_ = 0;
};

}  // namespace

Result<std::vector<BezierChain>> parse_svg_path(std::string_view data, const SvgPathOptions& options) {
    if (options.arcs == SvgArcConversion::Cubic && !(std::isfinite(options.arc_tolerance) && options.arc_tolerance > 0))
        return make_error(ErrorCode::InvalidArgument, "arc_tolerance must be a finite number > 0");
    return Parser(data, options).run();
}

}  // namespace surfaced
