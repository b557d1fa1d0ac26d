// Scene JSON -> implicit::Field (see scene_codec.h). Two passes over the DOM: the first collects every node that
// carries an "id" (so a ref may point forwards or backwards), the second builds fields depth-first, memoising id'd
// nodes (each is built once and shared) and detecting cycles with an in-progress set.
//
// Node forms (besides "op", every node may carry "id"):
//   sphere {radius}                 box {half_size}              rounded_box {half_size, radius}
//   torus {major_radius, minor_radius}                           cylinder {radius, half_height}
//   cone {radius, half_height, top_radius = 0}                   capsule {a, b, radius}
//   plane {normal, offset = 0}      ellipsoid {radii}
//   translate {offset, arg}         rotate {arg, axis + angle (degrees) | euler (degrees, x then y then z)}
//   scale {factor: s | [sx, sy, sz], arg}
//   union / intersection {args}     difference {args: first minus the rest}      blend {args: [a, b], t in [0, 1]}
//   smooth_union / smooth_intersection / smooth_difference {args, k > 0}
//   offset {arg, distance}          shell {arg, thickness}
//   expression {expr}               level_set {dims, origin, spacing: h | [hx, hy, hz], values}
//   mandelbulb {power = 8, iterations = 16, bailout = 2}          menger {iterations, half_size = 1}
//   mesh {mesh: {positions, faces} (the JSON mesh of every endpoint), winding = {accuracy = 2}}: signed distance
//   {"ref": "id"}                   reuses the node with that id
#include "api/scene_codec.h"

#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "api/json_codec.h"
#include "geometry/implicit/expression.h"
#include "geometry/implicit/fractals.h"
#include "geometry/implicit/level_set.h"
#include "geometry/implicit/operators.h"
#include "geometry/implicit/triangle_mesh_field.h"
#include "geometry/io/number_text.h"

namespace surfaced::api {
namespace {

using namespace json;  // the shared readers (api/json_util.h)
using implicit::FieldPtr;

//! Nesting depth of scene nodes (a guard on recursion, not a budget anyone should meet).
constexpr int kMaxSceneDepth = 100;
//! Largest winding accuracy (beta) of a mesh node: the hierarchy opens more nodes as beta grows, towards the exact
//! O(triangles) sum per evaluation, and a meshing grid evaluates the field up to max_grid_cells times.
constexpr double kMaxMeshWindingAccuracy = 10;

ApiError range_error(const std::string& field, const std::string& detail) {
    return geometry_error(ErrorCode::InvalidArgument, field, detail);
}

ApiError budget(const std::string& field, const std::string& detail) {
    return make_problem(Problem::BudgetExceeded, detail, field);
}

//! A scene's [x, y, z] (json::read_vec3 with the scene language's wording)
ApiResult<Vec3> read_scene_vec3(const Json& value, const std::string& field) {
    if (!value.is_array() || value.size() != 3) return invalid(field, field + " must be an array of 3 numbers");
    Vec3 v;
    for (std::size_t i = 0; i < 3; ++i) {
        auto x = read_number(value[i], index_path(field, i));
        if (!x) return std::move(x.error());
        v[static_cast<int>(i)] = x.value();
    }
    return v;
}

class SceneParser {
public:
    SceneParser(const Limits& limits, const Cancel& cancel) : limits_(limits), cancel_(cancel) {}

    ApiResult<FieldPtr> run(const Json& root, const std::string& path) {
        if (auto error = collect(root, path, 0)) return std::move(*error);
        return node(root, path, 0);
    }

private:
    struct Declared {
        const Json* node;
        std::string path;
    };

    //! Pass 1: every node that carries an id, by id (duplicates are an error).
    std::optional<ApiError> collect(const Json& v, const std::string& path, int depth) {
        if (depth > kMaxSceneDepth)
            return budget(path, "the scene is nested deeper than " + std::to_string(kMaxSceneDepth) + " nodes");
        if (!v.is_object()) return std::nullopt;  // reported by pass 2
        if (auto it = v.find("id"); it != v.end()) {
            const std::string field = member_path(path, "id");
            if (!it->is_string()) return invalid(field, field + " must be a string");
            const auto& id = it->get_ref<const std::string&>();
            if (auto [prev, inserted] = declared_.emplace(id, Declared{&v, path}); !inserted)
                return invalid(field, "id \"" + id + "\" is used twice (first at " + prev->second.path + ")");
        }
        if (auto it = v.find("op"); it != v.end() && it->is_string() && it->get_ref<const std::string&>() == "mesh")
            if (auto error = count_mesh(v, path)) return error;
        if (auto it = v.find("arg"); it != v.end())
            if (auto error = collect(*it, member_path(path, "arg"), depth + 1)) return error;
        if (auto it = v.find("args"); it != v.end() && it->is_array())
            for (std::size_t i = 0; i < it->size(); ++i)
                if (auto error = collect((*it)[i], index_path(member_path(path, "args"), i), depth + 1)) return error;
        return std::nullopt;
    }

    //! Pass 1, for a mesh node: its triangles and vertices added to the scene's totals, which must stay within
    //! max_input_faces and max_input_vertices (a node reused by ref counts once: it is built once). Malformed
    //! members count as nothing here; pass 2 reports them.
    std::optional<ApiError> count_mesh(const Json& v, const std::string& path) {
        const auto mesh = v.find("mesh");
        if (mesh == v.end() || !mesh->is_object()) return std::nullopt;
        if (const auto positions = mesh->find("positions"); positions != mesh->end() && positions->is_array())
            mesh_vertices_ += positions->size();
        if (const auto faces = mesh->find("faces"); faces != mesh->end() && faces->is_array())
            for (const Json& face : *faces)
                if (face.is_array() && face.size() >= 3) mesh_triangles_ += face.size() - 2;
        if (mesh_triangles_ > limits_.max_input_faces)
            return budget(path, "the scene's mesh nodes have " + std::to_string(mesh_triangles_) + " triangles up to " +
                                    path + "; the limit is " + std::to_string(limits_.max_input_faces));
        if (mesh_vertices_ > limits_.max_input_vertices)
            return budget(path, "the scene's mesh nodes have " + std::to_string(mesh_vertices_) + " vertices up to " +
                                    path + "; the limit is " + std::to_string(limits_.max_input_vertices));
        return std::nullopt;
    }

    //! Pass 2.
    ApiResult<FieldPtr> node(const Json& v, const std::string& path, int depth) {
        if (depth > kMaxSceneDepth)
            return budget(path, "the scene is nested deeper than " + std::to_string(kMaxSceneDepth) + " nodes");
        if (!v.is_object()) return invalid(path, path + R"( must be a scene node: {"op": ...} or {"ref": "id"})");
        if (auto it = v.find("ref"); it != v.end()) return reference(v, *it, path, depth);

        std::string id;
        if (auto it = v.find("id"); it != v.end()) {
            id = it->get<std::string>();  // a string: checked by collect()
            if (auto done = built_.find(id); done != built_.end()) return done->second;
        }
        if (++count_ > limits_.max_scene_nodes)
            return budget(path, "the scene has more than " + std::to_string(limits_.max_scene_nodes) + " nodes");
        if (!id.empty() || v.contains("id")) in_progress_.insert(id);
        auto field = op(v, path, depth);
        if (v.contains("id")) {
            in_progress_.erase(id);
            if (field) built_.emplace(id, field.value());
        }
        return field;
    }

    ApiResult<FieldPtr> reference(const Json& v, const Json& ref, const std::string& path, int depth) {
        const std::string field = member_path(path, "ref");
        if (auto error = check_members(v, path, {"ref"})) return std::move(*error);
        if (!ref.is_string()) return invalid(field, field + " must be a string (the id of another node)");
        const auto& id = ref.get_ref<const std::string&>();
        const auto target = declared_.find(id);
        if (target == declared_.end()) return invalid(field, field + ": no node has id \"" + id + "\"");
        if (in_progress_.count(id))
            return invalid(field, field + ": \"" + id + "\" refers to a node that contains this reference (a cycle)");
        if (auto done = built_.find(id); done != built_.end()) return done->second;
        if (++count_ > limits_.max_scene_nodes)
            return budget(path, "the scene has more than " + std::to_string(limits_.max_scene_nodes) + " nodes");
        return node(*target->second.node, target->second.path, depth + 1);
    }

    // --- member readers (the member is required unless a default is given) ---

    ApiResult<const Json*> member(const Json& v, const std::string& path, const char* name) {
        auto it = v.find(name);
        if (it == v.end()) return invalid(member_path(path, name), member_path(path, name) + " is required");
        return &*it;
    }

    ApiResult<double> number(const Json& v, const std::string& path, const char* name,
                             std::optional<double> fallback = std::nullopt) {
        if (fallback && !v.contains(name)) return *fallback;
        auto m = member(v, path, name);
        if (!m) return std::move(m.error());
        return read_number(*m.value(), member_path(path, name));
    }

    ApiResult<double> positive(const Json& v, const std::string& path, const char* name,
                               std::optional<double> fallback = std::nullopt) {
        auto x = number(v, path, name, fallback);
        if (x && !(x.value() > 0))
            return range_error(member_path(path, name), member_path(path, name) + " must be > 0");
        return x;
    }

    ApiResult<Vec3> vec3(const Json& v, const std::string& path, const char* name) {
        auto m = member(v, path, name);
        if (!m) return std::move(m.error());
        return read_scene_vec3(*m.value(), member_path(path, name));
    }

    ApiResult<Vec3> positive_vec3(const Json& v, const std::string& path, const char* name) {
        auto x = vec3(v, path, name);
        if (!x) return x;
        for (int i = 0; i < 3; ++i)
            if (!(x.value()[i] > 0)) {
                const std::string field = index_path(member_path(path, name), static_cast<std::size_t>(i));
                return range_error(field, field + " must be > 0");
            }
        return x;
    }

    ApiResult<int> iterations(const Json& v, const std::string& path, int minimum, std::optional<int> fallback) {
        const std::string field = member_path(path, "iterations");
        if (fallback && !v.contains("iterations")) return *fallback;
        auto m = member(v, path, "iterations");
        if (!m) return std::move(m.error());
        auto n = read_integer(*m.value(), field);
        if (!n) return std::move(n.error());
        if (n.value() < minimum) return range_error(field, field + " must be >= " + std::to_string(minimum));
        if (n.value() > limits_.max_fractal_iterations)
            return budget(field, field + " is " + std::to_string(n.value()) + "; the limit is " +
                                     std::to_string(limits_.max_fractal_iterations));
        return static_cast<int>(n.value());
    }

    ApiResult<FieldPtr> child(const Json& v, const std::string& path, int depth) {
        auto m = member(v, path, "arg");
        if (!m) return std::move(m.error());
        return node(*m.value(), member_path(path, "arg"), depth + 1);
    }

    ApiResult<std::vector<FieldPtr>> children(const Json& v, const std::string& path, int depth, std::size_t minimum,
                                              std::size_t maximum = 0) {
        const std::string field = member_path(path, "args");
        auto m = member(v, path, "args");
        if (!m) return std::move(m.error());
        const Json& args = *m.value();
        if (!args.is_array()) return invalid(field, field + " must be an array of scene nodes");
        if (args.size() < minimum || (maximum && args.size() > maximum))
            return invalid(field, field + (maximum == minimum ? " must have exactly " : " must have at least ") +
                                      std::to_string(minimum) + " nodes");
        std::vector<FieldPtr> out;
        for (std::size_t i = 0; i < args.size(); ++i) {
            auto c = node(args[i], index_path(field, i), depth + 1);
            if (!c) return std::move(c.error());
            out.push_back(std::move(c.value()));
        }
        return out;
    }

    // --- ops ---

    // One builder per op, each its own (non-inlined) function: the recursion node() -> op() -> build_*() -> node()
    // then carries only the locals of the ops on the path, which keeps deep scenes within the stack (ASan too).
#define SURFACED_MEMBERS(...) \
    if (auto error = check_members(v, path, {"op", "id", __VA_ARGS__})) return std::move(*error)
#define SURFACED_TRY(var, expr) \
    auto var = (expr);          \
    if (!var) return std::move(var.error())

    //! sphere
    [[gnu::noinline]] ApiResult<FieldPtr> build_sphere(const Json& v, const std::string& path,
                                                       [[maybe_unused]] int depth,
                                                       [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("radius");
        SURFACED_TRY(r, positive(v, path, "radius"));
        return implicit::sphere(r.value());
    }

    //! box
    [[gnu::noinline]] ApiResult<FieldPtr> build_box(const Json& v, const std::string& path, [[maybe_unused]] int depth,
                                                    [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("half_size");
        SURFACED_TRY(h, positive_vec3(v, path, "half_size"));
        return implicit::box(h.value());
    }

    //! rounded_box
    [[gnu::noinline]] ApiResult<FieldPtr> build_rounded_box(const Json& v, const std::string& path,
                                                            [[maybe_unused]] int depth,
                                                            [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("half_size", "radius");
        SURFACED_TRY(h, positive_vec3(v, path, "half_size"));
        SURFACED_TRY(r, number(v, path, "radius"));
        const Vec3& hs = h.value();
        if (r.value() < 0 || r.value() > std::min({hs.x, hs.y, hs.z}))
            return range_error(member_path(path, "radius"),
                               member_path(path, "radius") + " must be in [0, smallest half_size]");
        return implicit::rounded_box(hs, r.value());
    }

    //! torus
    [[gnu::noinline]] ApiResult<FieldPtr> build_torus(const Json& v, const std::string& path,
                                                      [[maybe_unused]] int depth,
                                                      [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("major_radius", "minor_radius");
        SURFACED_TRY(big, positive(v, path, "major_radius"));
        SURFACED_TRY(small, positive(v, path, "minor_radius"));
        return implicit::torus(big.value(), small.value());
    }

    //! cylinder
    [[gnu::noinline]] ApiResult<FieldPtr> build_cylinder(const Json& v, const std::string& path,
                                                         [[maybe_unused]] int depth,
                                                         [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("radius", "half_height");
        SURFACED_TRY(r, positive(v, path, "radius"));
        SURFACED_TRY(h, positive(v, path, "half_height"));
        return implicit::cylinder(r.value(), h.value());
    }

    //! cone
    [[gnu::noinline]] ApiResult<FieldPtr> build_cone(const Json& v, const std::string& path, [[maybe_unused]] int depth,
                                                     [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("radius", "half_height", "top_radius");
        SURFACED_TRY(r, positive(v, path, "radius"));
        SURFACED_TRY(h, positive(v, path, "half_height"));
        SURFACED_TRY(top, number(v, path, "top_radius", 0.0));
        if (top.value() < 0)
            return range_error(member_path(path, "top_radius"), member_path(path, "top_radius") + " must be >= 0");
        return implicit::cone(r.value(), h.value(), top.value());
    }

    //! capsule
    [[gnu::noinline]] ApiResult<FieldPtr> build_capsule(const Json& v, const std::string& path,
                                                        [[maybe_unused]] int depth,
                                                        [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("a", "b", "radius");
        SURFACED_TRY(a, vec3(v, path, "a"));
        SURFACED_TRY(b, vec3(v, path, "b"));
        SURFACED_TRY(r, positive(v, path, "radius"));
        return implicit::capsule(a.value(), b.value(), r.value());
    }

    //! plane
    [[gnu::noinline]] ApiResult<FieldPtr> build_plane(const Json& v, const std::string& path,
                                                      [[maybe_unused]] int depth,
                                                      [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("normal", "offset");
        SURFACED_TRY(n, vec3(v, path, "normal"));
        SURFACED_TRY(d, number(v, path, "offset", 0.0));
        if (!(norm(n.value()) > 0) || !std::isfinite(norm(n.value())))
            return range_error(member_path(path, "normal"), member_path(path, "normal") + " must be non-zero");
        return implicit::plane(n.value(), d.value());
    }

    //! ellipsoid
    [[gnu::noinline]] ApiResult<FieldPtr> build_ellipsoid(const Json& v, const std::string& path,
                                                          [[maybe_unused]] int depth,
                                                          [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("radii");
        SURFACED_TRY(r, positive_vec3(v, path, "radii"));
        return implicit::ellipsoid(r.value());
    }

    //! translate
    [[gnu::noinline]] ApiResult<FieldPtr> build_translate(const Json& v, const std::string& path,
                                                          [[maybe_unused]] int depth,
                                                          [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("offset", "arg");
        SURFACED_TRY(o, vec3(v, path, "offset"));
        SURFACED_TRY(c, child(v, path, depth));
        return implicit::translate(std::move(c.value()), o.value());
    }

    //! rotate
    [[gnu::noinline]] ApiResult<FieldPtr> build_rotate(const Json& v, const std::string& path,
                                                       [[maybe_unused]] int depth,
                                                       [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("arg", "axis", "angle", "euler");
        implicit::Mat3 rotation;
        if (v.contains("euler")) {
            if (v.contains("axis") || v.contains("angle"))
                return invalid(path, path + R"(: give either "axis" and "angle" or "euler", not both)");
            SURFACED_TRY(e, vec3(v, path, "euler"));
            rotation = implicit::rotation_euler(e.value());
        } else {
            SURFACED_TRY(axis, vec3(v, path, "axis"));
            SURFACED_TRY(angle, number(v, path, "angle"));
            const double n = norm(axis.value());
            if (!(n > 0) || !std::isfinite(n))
                return range_error(member_path(path, "axis"), member_path(path, "axis") + " must be non-zero");
            rotation = implicit::rotation_axis_angle(axis.value(), angle.value());
        }
        SURFACED_TRY(c, child(v, path, depth));
        return implicit::rotate(std::move(c.value()), rotation);
    }

    //! scale
    [[gnu::noinline]] ApiResult<FieldPtr> build_scale(const Json& v, const std::string& path,
                                                      [[maybe_unused]] int depth,
                                                      [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("factor", "arg");
        SURFACED_TRY(m, member(v, path, "factor"));
        if (m.value()->is_array()) {
            SURFACED_TRY(s, positive_vec3(v, path, "factor"));
            SURFACED_TRY(c, child(v, path, depth));
            return implicit::scale(std::move(c.value()), s.value());
        }
        SURFACED_TRY(s, positive(v, path, "factor"));
        SURFACED_TRY(c, child(v, path, depth));
        return implicit::scale(std::move(c.value()), s.value());
    }

    //! union, intersection
    [[gnu::noinline]] ApiResult<FieldPtr> build_boolean(const Json& v, const std::string& path,
                                                        [[maybe_unused]] int depth,
                                                        [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("args");
        SURFACED_TRY(args, children(v, path, depth, 1));
        return name == "union" ? implicit::csg_union(std::move(args.value()))
                               : implicit::csg_intersection(std::move(args.value()));
    }

    //! difference
    [[gnu::noinline]] ApiResult<FieldPtr> build_difference(const Json& v, const std::string& path,
                                                           [[maybe_unused]] int depth,
                                                           [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("args");
        SURFACED_TRY(args, children(v, path, depth, 2));
        return implicit::csg_difference(std::move(args.value()));
    }

    //! blend
    [[gnu::noinline]] ApiResult<FieldPtr> build_blend(const Json& v, const std::string& path,
                                                      [[maybe_unused]] int depth,
                                                      [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("args", "t");
        SURFACED_TRY(t, number(v, path, "t"));
        if (t.value() < 0 || t.value() > 1)
            return range_error(member_path(path, "t"), member_path(path, "t") + " must be in [0, 1]");
        SURFACED_TRY(args, children(v, path, depth, 2, 2));
        return implicit::blend(args.value()[0], args.value()[1], t.value());
    }

    //! smooth_union, smooth_intersection, smooth_difference
    [[gnu::noinline]] ApiResult<FieldPtr> build_smooth(const Json& v, const std::string& path,
                                                       [[maybe_unused]] int depth,
                                                       [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("args", "k");
        SURFACED_TRY(k, positive(v, path, "k"));
        SURFACED_TRY(args, children(v, path, depth, name == "smooth_difference" ? 2 : 1));
        if (name == "smooth_union") return implicit::smooth_union(std::move(args.value()), k.value());
        if (name == "smooth_intersection") return implicit::smooth_intersection(std::move(args.value()), k.value());
        return implicit::smooth_difference(std::move(args.value()), k.value());
    }

    //! offset
    [[gnu::noinline]] ApiResult<FieldPtr> build_offset(const Json& v, const std::string& path,
                                                       [[maybe_unused]] int depth,
                                                       [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("arg", "distance");
        SURFACED_TRY(d, number(v, path, "distance"));
        SURFACED_TRY(c, child(v, path, depth));
        return implicit::offset(std::move(c.value()), d.value());
    }

    //! shell
    [[gnu::noinline]] ApiResult<FieldPtr> build_shell(const Json& v, const std::string& path,
                                                      [[maybe_unused]] int depth,
                                                      [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("arg", "thickness");
        SURFACED_TRY(t, positive(v, path, "thickness"));
        SURFACED_TRY(c, child(v, path, depth));
        return implicit::shell(std::move(c.value()), t.value());
    }

    //! expression
    [[gnu::noinline]] ApiResult<FieldPtr> build_expression(const Json& v, const std::string& path,
                                                           [[maybe_unused]] int depth,
                                                           [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("expr");
        const std::string field = member_path(path, "expr");
        SURFACED_TRY(m, member(v, path, "expr"));
        if (!m.value()->is_string()) return invalid(field, field + " must be a string, e.g. \"x^2+y^2+z^2-1\"");
        implicit::ExpressionLimits el;
        el.max_nodes = static_cast<std::size_t>(limits_.max_expression_nodes);
        el.max_depth = limits_.max_expression_depth;
        auto parsed = implicit::parse_expression(m.value()->get_ref<const std::string&>(), el);
        if (!parsed) {
            const GeoError& e = parsed.error();
            if (e.code == ErrorCode::BudgetExceeded) return budget(field, field + ": " + e.message);
            return invalid(field, field + ": " + e.message);
        }
        return parsed.value();
    }

    //! mandelbulb
    [[gnu::noinline]] ApiResult<FieldPtr> build_mandelbulb(const Json& v, const std::string& path,
                                                           [[maybe_unused]] int depth,
                                                           [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("power", "iterations", "bailout");
        SURFACED_TRY(power, number(v, path, "power", 8.0));
        if (power.value() < 2 || power.value() > 32)
            return range_error(member_path(path, "power"), member_path(path, "power") + " must be in [2, 32]");
        SURFACED_TRY(n, iterations(v, path, 1, std::min(16, limits_.max_fractal_iterations)));
        SURFACED_TRY(bailout, number(v, path, "bailout", 2.0));
        if (bailout.value() < 2 || bailout.value() > 1e6)
            return range_error(member_path(path, "bailout"), member_path(path, "bailout") + " must be in [2, 1e6]");
        return implicit::mandelbulb(power.value(), n.value(), bailout.value());
    }

    //! menger
    [[gnu::noinline]] ApiResult<FieldPtr> build_menger(const Json& v, const std::string& path,
                                                       [[maybe_unused]] int depth,
                                                       [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("iterations", "half_size");
        SURFACED_TRY(n, iterations(v, path, 0, std::nullopt));
        SURFACED_TRY(h, positive(v, path, "half_size", 1.0));
        return implicit::menger_sponge(n.value(), h.value());
    }

    //! mesh: the signed distance to a triangle mesh (polygons triangulated), its sign by the winding number
    [[gnu::noinline]] ApiResult<FieldPtr> build_mesh(const Json& v, const std::string& path, [[maybe_unused]] int depth,
                                                     [[maybe_unused]] const std::string& name) {
        SURFACED_MEMBERS("mesh", "winding");
        const std::string mesh_field = member_path(path, "mesh");
        SURFACED_TRY(m, member(v, path, "mesh"));
        implicit::TriangleMeshFieldOptions options;
        if (auto it = v.find("winding"); it != v.end()) {
            const std::string winding_field = member_path(path, "winding");
            if (!it->is_object())
                return invalid(winding_field, winding_field + R"( must be an object {"accuracy": 2})");
            if (auto error = check_members(*it, winding_field, {"accuracy"})) return std::move(*error);
            SURFACED_TRY(beta, number(*it, winding_field, "accuracy", options.winding.accuracy));
            if (!(beta.value() > 1) || beta.value() > kMaxMeshWindingAccuracy) {
                const std::string field = member_path(winding_field, "accuracy");
                return range_error(field, field + " must be in (1, " + number_text(kMaxMeshWindingAccuracy) +
                                              "], got " + number_text(beta.value()));
            }
            options.winding.accuracy = beta.value();
        }
        SURFACED_TRY(mesh, decode_mesh_json(*m.value(), limits_, mesh_field));
        if (mesh.value().face_count() == 0) {
            const std::string field = member_path(mesh_field, "faces");
            return range_error(field, field + " is empty: a mesh node needs at least one face");
        }
        options.bvh.cancel = cancel_;
        auto built = implicit::triangle_mesh_field(mesh.value(), options);
        if (!built) {
            const GeoError& e = built.error();
            std::string field = mesh_field;
            if (e.element >= 0 && e.element_kind == ElementKind::Face)
                field = index_path(member_path(mesh_field, "faces"), static_cast<std::size_t>(e.element));
            else if (e.element >= 0 && e.element_kind == ElementKind::Vertex)
                field = index_path(member_path(mesh_field, "positions"), static_cast<std::size_t>(e.element));
            return geometry_error(e.code, field, field + ": " + e.message);
        }
        return std::move(built.value());
    }

    ApiResult<FieldPtr> op(const Json& v, const std::string& path, int depth) {
        const std::string op_field = member_path(path, "op");
        auto it = v.find("op");
        if (it == v.end()) return invalid(op_field, op_field + R"( is required (or use {"ref": "id"}))");
        if (!it->is_string()) return invalid(op_field, op_field + " must be a string");
        const std::string name = it->get<std::string>();
        if (name == "sphere") return build_sphere(v, path, depth, name);
        if (name == "box") return build_box(v, path, depth, name);
        if (name == "rounded_box") return build_rounded_box(v, path, depth, name);
        if (name == "torus") return build_torus(v, path, depth, name);
        if (name == "cylinder") return build_cylinder(v, path, depth, name);
        if (name == "cone") return build_cone(v, path, depth, name);
        if (name == "capsule") return build_capsule(v, path, depth, name);
        if (name == "plane") return build_plane(v, path, depth, name);
        if (name == "ellipsoid") return build_ellipsoid(v, path, depth, name);
        if (name == "translate") return build_translate(v, path, depth, name);
        if (name == "rotate") return build_rotate(v, path, depth, name);
        if (name == "scale") return build_scale(v, path, depth, name);
        if (name == "union" || name == "intersection") return build_boolean(v, path, depth, name);
        if (name == "difference") return build_difference(v, path, depth, name);
        if (name == "blend") return build_blend(v, path, depth, name);
        if (name == "smooth_union" || name == "smooth_intersection" || name == "smooth_difference")
            return build_smooth(v, path, depth, name);
        if (name == "offset") return build_offset(v, path, depth, name);
        if (name == "shell") return build_shell(v, path, depth, name);
        if (name == "expression") return build_expression(v, path, depth, name);
        if (name == "mandelbulb") return build_mandelbulb(v, path, depth, name);
        if (name == "menger") return build_menger(v, path, depth, name);
        if (name == "level_set") return level_set(v, path);
        if (name == "mesh") return build_mesh(v, path, depth, name);
        return invalid(op_field, op_field + ": unknown op \"" + name +
                                     "\" (sphere, box, rounded_box, torus, cylinder, cone, capsule, plane, ellipsoid, "
                                     "translate, rotate, scale, union, intersection, difference, blend, smooth_union, "
                                     "smooth_intersection, smooth_difference, offset, shell, expression, level_set, "
                                     "mandelbulb, menger, mesh)");
    }
#undef SURFACED_MEMBERS
#undef SURFACED_TRY

    ApiResult<FieldPtr> level_set(const Json& v, const std::string& path) {
        if (auto error = check_members(v, path, {"op", "id", "dims", "origin", "spacing", "values"}))
            return std::move(*error);
        implicit::LevelSetGrid grid;
        const std::string dims_field = member_path(path, "dims");
        auto dims = member(v, path, "dims");
        if (!dims) return std::move(dims.error());
        if (!dims.value()->is_array() || dims.value()->size() != 3)
            return invalid(dims_field, dims_field + " must be [nx, ny, nz]");
        // Budget before reading a single value: each axis and the product against max_level_set_samples.
        std::uint64_t count = 1;
        for (std::size_t a = 0; a < 3; ++a) {
            const std::string field = index_path(dims_field, a);
            auto n = read_integer((*dims.value())[a], field);
            if (!n) return std::move(n.error());
            if (n.value() < 2) return range_error(field, field + " must be >= 2");
            const auto un = static_cast<std::uint64_t>(n.value());
            if (un > limits_.max_level_set_samples || count * un > limits_.max_level_set_samples)
                return budget(dims_field, dims_field + " asks for more than " +
                                              std::to_string(limits_.max_level_set_samples) + " samples");
            count *= un;
            grid.dims[a] = static_cast<std::size_t>(un);
        }
        auto origin = vec3(v, path, "origin");
        if (!origin) return std::move(origin.error());
        grid.origin = origin.value();
        const std::string spacing_field = member_path(path, "spacing");
        auto spacing = member(v, path, "spacing");
        if (!spacing) return std::move(spacing.error());
        if (spacing.value()->is_array()) {
            auto s = positive_vec3(v, path, "spacing");
            if (!s) return std::move(s.error());
            grid.spacing = s.value();
        } else {
            auto s = positive(v, path, "spacing");
            if (!s) return std::move(s.error());
            grid.spacing = {s.value(), s.value(), s.value()};
        }
        const std::string values_field = member_path(path, "values");
        auto values = member(v, path, "values");
        if (!values) return std::move(values.error());
        const Json& array = *values.value();
        if (!array.is_array()) return invalid(values_field, values_field + " must be an array of numbers");
        if (array.size() != count)
            return invalid(values_field, values_field + " has " + std::to_string(array.size()) + " values; dims " +
                                             std::to_string(grid.dims[0]) + "x" + std::to_string(grid.dims[1]) + "x" +
                                             std::to_string(grid.dims[2]) + " needs " + std::to_string(count));
        grid.values.reserve(count);
        for (std::size_t i = 0; i < array.size(); ++i) {
            const Json& x = array[i];
            if (!x.is_number() || !std::isfinite(x.get<double>()))
                return invalid(index_path(values_field, i), index_path(values_field, i) + " must be a finite number");
            grid.values.push_back(x.get<double>());
        }
        auto field = implicit::level_set(std::move(grid));
        if (!field) return geometry_error(field.error().code, path, path + ": " + field.error().message);
        return field.value();
    }

    const Limits& limits_;
    Cancel cancel_;
    std::map<std::string, Declared> declared_;
    std::map<std::string, FieldPtr> built_;
    std::set<std::string> in_progress_;
    std::uint64_t count_ = 0;
    std::uint64_t mesh_triangles_ = 0, mesh_vertices_ = 0;  //!< over every mesh node (pass 1)
};

}  // namespace

ApiResult<std::shared_ptr<const implicit::Field>> parse_scene(const json::Json& node, const Limits& limits,
                                                              const std::string& path, const Cancel& cancel) {
    SceneParser parser(limits, cancel);
    return parser.run(node, path);
}

ApiResult<Box3> parse_bounds(const json::Json& value, const std::string& path) {
    if (!value.is_array() || value.size() != 2)
        return json::invalid(path, path + " must be [[xmin, ymin, zmin], [xmax, ymax, zmax]]");
    auto lo = read_scene_vec3(value[0], json::index_path(path, 0));
    if (!lo) return std::move(lo.error());
    auto hi = read_scene_vec3(value[1], json::index_path(path, 1));
    if (!hi) return std::move(hi.error());
    Box3 box;
    box.min = lo.value();
    box.max = hi.value();
    for (int a = 0; a < 3; ++a)
        if (!(box.min[a] < box.max[a])) {
            const std::string field = json::index_path(json::index_path(path, 1), static_cast<std::size_t>(a));
            return range_error(field, path + ": min must be < max on every axis (axis " + std::to_string(a) + ")");
        }
    return box;
}

}  // namespace surfaced::api
