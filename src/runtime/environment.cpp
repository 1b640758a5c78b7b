#include "olt/runtime/environment.h"

#include <stdexcept>

namespace olt {

const StageKind& Environment::kind(const std::string& name) const {
  for (const auto& k : *kinds)
    if (k.spec.name == name) return k;
  throw std::out_of_range("unknown stage kind " + name);
}

}  // namespace olt
