// `--param name=value` lists decoded by a stage's schema (arcs reconstruct,
// for an sdf_to_mesh stage and for a point-cloud reconstructor alike).
//
// A stage-valued parameter takes the form `--help` prints its default in,
// so a default can be copied, edited and passed back:
//   --param 'reconstructor=screened_poisson(normal_splat=ceil, point_weight=15)'
// A bare name (`reconstructor=screened_poisson`) is that stage with nothing
// given. As in an experiment file, a nested stage named like the parameter's
// default starts from the default's parameters (here rfta's official call)
// and the ones written replace them; nested stages nest
// (`sampler=rasterize(...)` inside another stage's list).
#pragma once

#include "registry/registry.h"

#include <string>
#include <vector>

namespace arcs {

// The parameters given in `kvs` ("name=value" each) for `stage`, typed by
// its schema, unresolved (Registry::Resolve fills the defaults and checks the
// values). Bad usage (no '=', an unknown name, a value of the wrong type,
// unbalanced parentheses) exits through cli::Usage, naming `flag`.
ParamMap DecodeGivenParams(const Registry& registry, const std::string& stage, const std::vector<std::string>& kvs,
                           const std::string& flag);

}  // namespace arcs
