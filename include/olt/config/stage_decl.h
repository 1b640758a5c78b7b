#pragma once
// A stage as a job declares it, and what a stage kind tells validation about itself: the two sides
// that meet when a job is loaded (olt/job/job.h) without either depending on the other.
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "olt/config/document.h"
#include "olt/config/params.h"

namespace olt {

struct StageDecl {
  std::string id;
  std::string kind;
  std::vector<std::string> needs;
  nlohmann::json params;  ///< canonical: defaults filled in, paths absolute
  /// Upstream stage id feeding each artifact kind this stage reads (resolved through `needs`).
  std::map<std::string, std::string> inputs;
  std::string pointer;  ///< JSON pointer of the stage in the job document, for messages
};

/// What validation needs to know about a stage kind.
struct KindSpec {
  std::string name;
  std::shared_ptr<const FieldTable> params;
  std::vector<std::string> reads;           ///< artifact kinds it must find upstream
  std::vector<std::string> optional_reads;  ///< artifact kinds it uses when found upstream
  /// Checks beyond single fields (combinations, files named by the params, upstream kinds).
  /// `upstream` maps each resolved input kind to its stage.
  std::function<void(const StageDecl& stage, const std::map<std::string, const StageDecl*>& upstream,
                     const Document& doc, std::vector<Diagnostic>& errors)>
      check;
};

}  // namespace olt
