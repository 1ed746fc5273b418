//! CSE: every method evaluates each distinct subexpression once.

use std::collections::{HashMap, HashSet};

use super::{double_pendulum_item, model};
use crate::cse::{self, Plan, gradient_roots, hessian_roots};
use crate::ir::{Graph, Id, Node};

/// Walks what a plan emits — each temporary's definition and each root — and returns the
/// operations evaluated, each as the full expansion of its subtree (independent of node ids),
/// and the expansions of the temporaries' definitions.
fn evaluated_subtrees(g: &Graph, plan: &Plan, roots: &[Id]) -> (Vec<String>, Vec<String>) {
    fn key(g: &Graph, id: Id, memo: &mut HashMap<Id, String>) -> String {
        if let Some(k) = memo.get(&id) {
            return k.clone();
        }
        let node = g.node(id);
        let children: Vec<String> = node.children().iter().map(|&c| key(g, c, memo)).collect();
        let head = match node {
            Node::Num(bits) => format!("{:?}", f64::from_bits(bits)),
            Node::Var(v) => format!("{v:?}"),
            Node::Add(..) => "+".into(),
            Node::Sub(..) => "-".into(),
            Node::Mul(..) => "*".into(),
            Node::Div(..) => "/".into(),
            Node::Neg(_) => "neg".into(),
            Node::Call(f, _) => f.name().into(),
            Node::Powi(_, n) => format!("powi{n}"),
            Node::Powf(..) => "powf".into(),
            Node::Hypot(..) => "hypot".into(),
            Node::Atan2(..) => "atan2".into(),
            Node::Select(op, ..) => format!("select{}", op.symbol()),
            Node::Sum(i, _) => format!("sum{}", i.0),
        };
        let k = format!("{head}({})", children.join(","));
        memo.insert(id, k.clone());
        k
    }
    fn walk(g: &Graph, plan: &Plan, id: Id, top: bool, out: &mut Vec<Id>) {
        if g.node(id).is_leaf() || (!top && plan.temp(id).is_some()) {
            return; // a leaf or a read of a temporary: nothing evaluated
        }
        out.push(id);
        for c in g.node(id).children() {
            walk(g, plan, c, false, out);
        }
    }
    let mut evaluated = Vec::new();
    for &t in &plan.temps {
        walk(g, plan, t, true, &mut evaluated);
    }
    for &r in roots {
        if plan.temp(r).is_none() {
            walk(g, plan, r, true, &mut evaluated);
        }
    }
    let mut memo = HashMap::new();
    let all = evaluated.iter().map(|&id| key(g, id, &mut memo)).collect();
    let defs = plan.temps.iter().map(|&id| key(g, id, &mut memo)).collect();
    (all, defs)
}

fn duplicates(keys: &[String]) -> Vec<&String> {
    let mut seen = HashSet::new();
    keys.iter().filter(|k| !seen.insert(*k)).collect()
}

#[test]
fn double_pendulum_hessian_evaluates_each_subexpression_once() {
    let (model, d) = model(double_pendulum_item());
    let g = &model.graph;
    let plans = cse::plan(g, model.root, &d);
    let roots = hessian_roots(g, &d);
    let (keys, defs) = evaluated_subtrees(g, &plans.hessian, &roots);
    assert!(
        keys.len() > 10,
        "the hessian evaluates {} operations",
        keys.len()
    );
    assert!(
        duplicates(&keys).is_empty(),
        "evaluated twice: {:?}",
        duplicates(&keys)
    );
    // Every temporary's defining expression is distinct.
    assert!(!defs.is_empty());
    assert!(
        duplicates(&defs).is_empty(),
        "temporaries repeat: {:?}",
        duplicates(&defs)
    );

    // The same holds for every other emitted method.
    let both: Vec<Id> = gradient_roots(&d)
        .into_iter()
        .chain(roots.clone())
        .collect();
    let methods = [
        (&plans.value, vec![model.root]),
        (&plans.gradient, gradient_roots(&d)),
        (&plans.gradient_and_hessian, both),
    ];
    for (plan, roots) in &methods {
        let (keys, _) = evaluated_subtrees(g, plan, roots);
        assert!(
            duplicates(&keys).is_empty(),
            "evaluated twice: {:?}",
            duplicates(&keys)
        );
    }

    // Negative control: without temporaries the hessian does repeat work, so the check above
    // is able to fail.
    let inline = Plan::without_temps(g);
    let (keys, _) = evaluated_subtrees(g, &inline, &roots);
    assert!(!duplicates(&keys).is_empty());
}

/// `gradient_and_hessian` is one plan: what the gradient and the Hessian share (here
/// `cos(x[0] − x[1])`, `sin(x[0] − x[1])` and the products of the constants) is evaluated once,
/// so it costs fewer operations than calling `gradient` and `hessian`.
#[test]
fn gradient_and_hessian_shares_work_between_gradient_and_hessian() {
    let (model, d) = model(double_pendulum_item());
    let g = &model.graph;
    let plans = cse::plan(g, model.root, &d);
    let gradient = gradient_roots(&d);
    let hessian = hessian_roots(g, &d);
    let both: Vec<Id> = gradient.iter().chain(&hessian).copied().collect();
    let count = |plan: &Plan, roots: &[Id]| evaluated_subtrees(g, plan, roots).0.len();
    let separate = count(&plans.gradient, &gradient) + count(&plans.hessian, &hessian);
    let fused = count(&plans.gradient_and_hessian, &both);
    assert!(
        fused < separate,
        "gradient_and_hessian evaluates {fused} operations, gradient + hessian {separate}"
    );
    // Nothing is evaluated in the fused plan that the two separate ones do not need.
    let (fused_keys, _) = evaluated_subtrees(g, &plans.gradient_and_hessian, &both);
    let (mut separate_keys, _) = evaluated_subtrees(g, &plans.gradient, &gradient);
    separate_keys.extend(evaluated_subtrees(g, &plans.hessian, &hessian).0);
    let separate_keys: HashSet<&String> = separate_keys.iter().collect();
    assert!(fused_keys.iter().all(|k| separate_keys.contains(k)));
}
