#pragma once
// What `artemis view` and `artemis run --viewer` share: the query answer (the same QueryGrounder
// as `artemis ground`), the classes the page lists, the address line, and waiting for Ctrl-C.

#include <memory>
#include <string_view>
#include <vector>

#include "artemis/semantics/active_brush.hpp"
#include "artemis/semantics/vocabulary.hpp"
#include "server.hpp"

namespace artemis::viewer {

// Grounds a query against `vocabulary`. The answer lists every matched class with its highlight
// colour (in the order of the answer) and whether the map holds it: `labelled` are the classes
// the map was segmented for; with a `brush` (a live run) a matched class the map does not hold yet
// is added to the segmenter's prompts from the next frame on, as `artemis run --query` does.
// Returns an error for a malformed or empty query; a query matching nothing is an answer with an
// empty "matched" and a "message" saying so.
Result<QueryFn> makeQueryFn(semantics::Vocabulary vocabulary, std::vector<semantics::ClassId> labelled,
                            semantics::ActiveBrush* brush = nullptr);

// [{"id", "name", "rgb"}] of `classes` (display colours of the vocabulary).
nlohmann::json classesJson(const semantics::Vocabulary& vocabulary, const std::vector<semantics::ClassId>& classes);

// classesJson of every class of the vocabulary (the page's class colours).
nlohmann::json vocabularyJson(const semantics::Vocabulary& vocabulary);

// Prints "viewer: <url> (<note>)" on stdout, the address the server is bound to, and, when other
// machines can connect (any host but a loopback address), a warning on the log that the map and
// the run folder are served to them without authentication.
void announce(const Server& server, std::string_view note);

// Blocks until SIGINT or SIGTERM, or `seconds` (< 0: no limit).
void waitForInterrupt(double seconds = -1.0);

}  // namespace artemis::viewer
