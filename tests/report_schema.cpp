#include "report_schema.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>
#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validation_results.hpp>
#include <valijson/validator.hpp>

namespace mrjam_test {
namespace {

nlohmann::json read_json_file(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    return nlohmann::json::parse(in);
}

// Parsed once per mode: the suite checks hundreds of reports against eight schemas.
const valijson::Schema& schema_of(const std::string& path) {
    static std::map<std::string, std::unique_ptr<valijson::Schema>> parsed;
    auto found = parsed.find(path);
    if (found != parsed.end()) return *found->second;
    const nlohmann::json document = read_json_file(path);
    auto schema = std::make_unique<valijson::Schema>();
    valijson::SchemaParser parser(valijson::SchemaParser::kDraft7);
    valijson::adapters::NlohmannJsonAdapter adapter(document);
    parser.populateSchema(adapter, *schema);
    return *parsed.emplace(path, std::move(schema)).first->second;
}

// valijson's context ("<root>", "[results]", "[steps]") as a JSON pointer ("/results/steps").
std::string json_path(const std::vector<std::string>& context) {
    std::string out;
    for (const std::string& part : context) {
        if (part == "<root>") continue;
        const bool bracketed = part.size() >= 2 && part.front() == '[' && part.back() == ']';
        out += "/" + (bracketed ? part.substr(1, part.size() - 2) : part);
    }
    return out.empty() ? "/" : out;
}

}  // namespace

std::string report_schema_path(const std::string& mode) {
    const std::string name = mode.rfind("asteroid", 0) == 0 ? "asteroid" : mode;
    // A mode is a word with hyphens; anything else names no file under schemas/.
    if (name.empty() || !std::all_of(name.begin(), name.end(), [](char c) { return std::islower(c) || c == '-'; }))
        return "";
    const std::string path = std::string(MRJAM_SOURCE_DIR) + "/schemas/report_" + name + ".schema.json";
    return std::filesystem::exists(path) ? path : "";
}

std::vector<std::string> report_schema_errors(const nlohmann::json& report) {
    if (!report.is_object() || !report.contains("mode") || !report["mode"].is_string())
        return {"/mode: a report names its mode as a string"};
    const std::string path = report_schema_path(report["mode"].get<std::string>());
    if (path.empty()) return {"/mode: no schema for mode '" + report["mode"].get<std::string>() + "'"};
    valijson::Validator validator;
    valijson::ValidationResults results;
    valijson::adapters::NlohmannJsonAdapter target(report);
    std::vector<std::string> errors;
    if (!validator.validate(schema_of(path), target, &results)) {
        valijson::ValidationResults::Error error;
        while (results.popError(error)) errors.push_back(json_path(error.context) + ": " + error.description);
    }
    return errors;
}

std::vector<std::string> report_file_schema_errors(const std::string& path) {
    try {
        return report_schema_errors(read_json_file(path));
    } catch (const std::exception& e) {
        return {path + ": " + e.what()};
    }
}

}  // namespace mrjam_test
