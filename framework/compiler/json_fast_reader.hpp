// Reads a JSON text straight from its bytes, the usual way the JSON reader reads one
// (readJson): strings without escapes are viewed where they are, and no value is allocated.
#pragma once

#include "json_document_builder.hpp"

#include <string_view>

namespace skygraph {

/// Reads `text` into `builder`, giving the events and values nlohmann's parser would give.
/// Returns false where it gives up: at every error, and at the few valid forms it leaves to
/// nlohmann (a byte-order mark, an integer of 19 digits or more, a float that underflows);
/// the builder's document is then to be dropped, and the text read by nlohmann.
[[nodiscard]] bool readJsonFast(std::string_view text, JsonDocumentBuilder& builder);

}  // namespace skygraph
