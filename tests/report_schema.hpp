#pragma once
// Every report a test makes mrjam write is checked against its mode's JSON Schema in schemas/
// (draft-07, validated with valijson), so a key that goes missing or changes type fails the suite
// where it happens instead of in a user's script.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mrjam_test {

// The schema file of a report's `mode` ("asteroid <kind>" share one), or "" for none.
std::string report_schema_path(const std::string& mode);
// Each way `report` breaks its mode's schema, as "JSON path: what" lines; empty when it conforms.
// A report without a string `mode`, or one whose mode has no schema, is an error too.
std::vector<std::string> report_schema_errors(const nlohmann::json& report);
// The same for the report file at `path`; an unreadable or unparsable file is an error.
std::vector<std::string> report_file_schema_errors(const std::string& path);

}  // namespace mrjam_test
