//! Graph-level params (`shared_params`): one value for every instance whose pass has the param,
//! so a choice several passes must agree on (the sampler, whether sample indices restart) is
//! written once. An instance's own value wins.

use super::compose::PassOrigin;
use super::decl::PassInstanceDecl;
use super::error::GraphError;
use super::id::{IdVec, PassIndex};
use super::load::LoadedGraph;
use super::provided::ProvidedSet;

/// Each instance with the graph's shared params it takes added to its own, and its origin
/// naming the file that set each (for errors); every shared param must reach some pass.
pub fn with_shared_params(
    graph: &LoadedGraph,
    provided: &ProvidedSet,
) -> Result<IdVec<PassIndex, (PassOrigin, PassInstanceDecl)>, GraphError> {
    let shared = &graph.decl.shared_params;
    let mut reached = vec![false; shared.len()];
    let mut instances = IdVec::from(Vec::with_capacity(graph.decl.passes.len()));
    for instance in &graph.decl.passes {
        let params = graph.passes[&instance.pass].params(provided);
        let mut origin = graph.pass_origin(&instance.name);
        let mut instance = instance.clone();
        for (i, (name, value)) in shared.iter().enumerate() {
            if !params.contains_key(name) {
                continue;
            }
            reached[i] = true;
            if !instance.params.contains_key(name) {
                instance.params.insert(name.clone(), value.clone());
                let file = graph.origins.shared_params.get(name);
                origin
                    .params
                    .insert(name.clone(), file.unwrap_or(&graph.file).clone());
            }
        }
        instances.push((origin, instance));
    }
    if let Some((name, _)) = shared.keys().zip(&reached).find(|&(_, &r)| !r) {
        return Err(GraphError::UnusedSharedParam {
            graph: graph
                .origins
                .shared_params
                .get(name)
                .unwrap_or(&graph.file)
                .clone(),
            param: name.clone(),
            passes: graph.decl.passes.iter().map(|p| p.name.clone()).collect(),
        });
    }
    Ok(instances)
}
