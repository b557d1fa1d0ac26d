#include "server/cli/output.h"

namespace surfaced::cli {

std::string header(const api::ApiResponse& response, std::string_view name) {
    for (const auto& [key, value] : response.headers)
        if (key == name) return value;
    return "?";
}

int print_problem(const api::ApiResponse& response, const Parsed& parsed, ProblemStyle style) {
    const auto& problem = response.error;
    if (!problem) {
        std::cerr << "surfaced: " << parsed.input_label() << ": failed with status " << response.status << "\n";
        return kExitFailed;
    }
    // a budget (422 budget_exceeded) is the operation's limit, not a wrong value: exit 1 like any other failure
    const bool bad_value = response.status == 400 || (response.status == 422 && problem->code != "budget_exceeded");
    if (bad_value && problem->field)
        if (const auto option = parsed.option_for_field(*problem->field)) {
            std::cerr << "surfaced: " << parsed.command << " " << *option << ": " << problem->detail << "\n";
            return kExitUsage;
        }
    std::cerr << "surfaced: " << parsed.input_label() << ": ";
    if (style.field && problem->field && !problem->field->empty() && !problem->detail.starts_with(*problem->field))
        std::cerr << *problem->field << ": ";
    std::cerr << problem->detail;
    if (style.line && problem->line)
        std::cerr << " (line " << *problem->line << ")";
    else if (style.offset && problem->offset)
        std::cerr << " (byte offset " << *problem->offset << ")";
    std::cerr << " [" << problem->code << "]\n";
    return kExitFailed;
}

void print_repairs(const Parsed& parsed, const api::ApiResponse& response, bool always) {
    const std::string repairs = header(response, "X-Repairs");
    if (repairs == "?") return;
    bool any = always;
    for (std::size_t at = repairs.find('='); at != std::string::npos; at = repairs.find('=', at + 1)) {
        const std::size_t name = repairs.rfind(' ', at) == std::string::npos ? 0 : repairs.rfind(' ', at) + 1;
        if (repairs.compare(name, at - name, "components") != 0 && repairs[at + 1] != '0') any = true;
    }
    if (any) std::cerr << "repaired " << parsed.input_label() << ": " << repairs << "\n";
}

void print_triangulated_result(const Parsed& parsed, const api::ApiResponse& response) {
    parsed.report() << "wrote " << parsed.output_label() << ": " << header(response, "X-Output-Faces") << " triangles, "
                    << header(response, "X-Output-Vertices") << " vertices (from " << header(response, "X-Input-Faces")
                    << " faces" << (header(response, "X-Triangulated") == "true" ? ", triangulated first" : "") << ")";
}

}  // namespace surfaced::cli
