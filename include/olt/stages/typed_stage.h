#pragma once
// A stage kind's body from its typed parts: the codec's `load` (input artifacts to typed inputs),
// the stage's function (inputs and config to a result), and the codec's `save` (the result to
// artifact files, the publish list and the summary). Only the codec knows the artifacts' file names;
// the function writes nothing. It does read the files its inputs name — depth and colour images,
// a user's annotation or trajectory file — one at a time, as a recording of thousands of images
// cannot be loaded whole.
#include <memory>

#include "olt/config/params.h"
#include "olt/stages/stage.h"

namespace olt {

template <typename Config, typename Inputs, typename Result>
StageFunction typed_stage(std::shared_ptr<const Params<Config>> params, Inputs (*load)(const StageContext&),
                          Result (*run)(const Inputs&, const Config&),
                          nlohmann::json (*save)(const Result&, const StageContext&, ArtifactWriter&)) {
  return [=](const StageContext& context, ArtifactWriter& out) {
    const Config config = params->from_json(context.stage.params);
    return save(run(load(context), config), context, out);
  };
}

}  // namespace olt
