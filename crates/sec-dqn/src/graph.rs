//! ERLAM's associative memory graph, as the authors' `AssociativeMemory` keeps it: a node per
//! distinct state (its trained-autoencoder embedding, merged with the nearest stored node when it
//! lies within `mergeDistance`), holding its transition, the best return seen from it (Rt), and
//! links to the nodes that followed it. At every episode's end the episode is added backwards
//! with discounted returns; every `propagateEvery` episodes Rt is propagated through the links
//! until the total change is at most 1e-6. The network samples its training batches from the
//! nodes, with the graph's value of each node's successor as the second target.
//!
//! Two quirks of the authors' code are kept, because their numbers come from them:
//! - a full graph evicts its least recently improved node as soon as it reaches the capacity, so
//!   it holds capacity - 1 nodes, and the eviction re-keys every node's links by node id instead
//!   of by action, so a link made before an eviction no longer counts for the graph's value;
//! - the merge test uses a k-d tree of the nodes as they were when the episode ended.

use crate::ErlamConfig;
use kiddo::immutable::float::kdtree::ImmutableKdTree;
use kiddo::SquaredEuclidean;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use sec_playground::encoder::EMBEDDING;
use sec_playground::memory::ACTIONS;
use std::collections::{BTreeMap, HashMap};

/// The most sweeps one propagation makes (it stops there if it has not converged).
const MAX_SWEEPS: usize = 100_000;

/// What a node's links are keyed by: the action that led to the next node, or (after an
/// eviction re-keyed them, as the authors' code does) that node's id.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum LinkKey {
    /// The action (0..=8) taken from the node.
    Action(u8),
    /// The id of the node an evicted link was re-keyed by.
    Node(u64),
}

/// A node's id, stamp, Rt (bits) and sorted links: what two graphs are compared by in tests.
#[cfg(test)]
type NodeLinks = (u64, u64, u64, Vec<(LinkKey, u64)>);

/// One state of the graph: the transition that stored it and what propagation made of it.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Node {
    /// Its id (ids are never reused).
    pub id: u64,
    /// The state's embedding, its key.
    pub embedding: [f32; EMBEDDING],
    /// The state's frame (84x84 RGB bytes), which the network's second target trains on.
    #[serde(with = "serde_bytes")]
    pub state: Vec<u8>,
    /// The frame of the state its transition led to.
    #[serde(with = "serde_bytes")]
    pub next_state: Vec<u8>,
    /// Position in the episode that created it (value propagation goes from the latest).
    pub t: usize,
    /// The action taken from it (0..=8).
    pub action: u8,
    /// The reward of its transition.
    pub reward: f32,
    /// Whether its transition ended the episode.
    pub done: bool,
    /// The best discounted return seen from this node.
    pub rt: f64,
    /// Successor node ids.
    pub next: HashMap<LinkKey, u64>,
    /// When its value last improved (unique; the least is evicted first).
    pub stamp: u64,
}

/// One transition of the episode in progress.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Pending {
    /// The state's embedding.
    pub embedding: [f32; EMBEDDING],
    /// The state's frame.
    #[serde(with = "serde_bytes")]
    pub state: Vec<u8>,
    /// The next state's frame.
    #[serde(with = "serde_bytes")]
    pub next_state: Vec<u8>,
    /// The action taken (0..=8).
    pub action: u8,
    /// The transition's reward.
    pub reward: f32,
    /// Whether it ended the episode.
    pub done: bool,
}

/// A checkpoint holds everything but the settings (the run's own) and `by_bits` (rebuilt).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Graph {
    #[serde(skip)]
    cfg: ErlamConfig,
    #[serde(skip)]
    gamma: f64,
    nodes: HashMap<u64, Node>,
    /// Node ids in insertion order (the authors' dict order, which their sampling indexes).
    order: Vec<u64>,
    /// Exact embeddings to their node (the authors' hash keys).
    #[serde(skip)]
    by_bits: HashMap<[u32; EMBEDDING], u64>,
    /// Stamps (unique) to their node, so that the least recently improved node is the first.
    #[serde(skip)]
    by_stamp: BTreeMap<u64, u64>,
    next_id: u64,
    stamp: u64,
    episode: Vec<Pending>,
    /// Sweeps the last propagation needed.
    pub last_sweeps: usize,
}

/// What a graph's values rest on (`erlam-graph`): how many nodes the network's second target
/// finds a successor for, where the rewards sit, and how far the rest are from them.
#[derive(Clone, Debug, PartialEq)]
pub struct Census {
    /// Nodes in the graph.
    pub nodes: usize,
    /// Nodes whose own action has a link, so that `value` is not 0.
    pub valued: usize,
    /// Nodes stored with a positive reward, and how many of those are terminal yet have a
    /// successor (a later, non-terminal state merged into them, so propagation carries on past
    /// the goal: the authors' propagation does not look at `done`).
    pub rewarded: usize,
    /// Of `rewarded`, the terminal ones with a successor.
    pub rewarded_linked: usize,
    /// The largest reward stored.
    pub max_reward: f64,
    /// `value` of every node, ascending.
    pub values: Vec<f64>,
    /// Links to a rewarded node from each node that has a path to one, ascending.
    pub hops: Vec<usize>,
}

impl Census {
    /// The `p` quantile (0..=1, nearest rank below) of a sorted list.
    pub fn quantile<T: Copy>(sorted: &[T], p: f64) -> Option<T> {
        (!sorted.is_empty()).then(|| sorted[((sorted.len() - 1) as f64 * p) as usize])
    }
}

/// A node's links as the authors' eviction leaves them: keyed by the node they lead to, without
/// the evicted one.
fn rekeyed(next: &HashMap<LinkKey, u64>, evicted: u64) -> HashMap<LinkKey, u64> {
    next.values().filter(|&&n| n != evicted).map(|&n| (LinkKey::Node(n), n)).collect()
}

fn sq_dist(a: &[f32; EMBEDDING], b: &[f32; EMBEDDING]) -> f32 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

impl Graph {
    /// An empty graph of `cfg`, discounting by `gamma` when it propagates.
    pub fn new(cfg: ErlamConfig, gamma: f64) -> Self {
        Graph { cfg, gamma, ..Graph::default() }
    }

    /// What it was built with.
    pub fn config(&self) -> &ErlamConfig {
        &self.cfg
    }

    /// Nodes stored.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// A graph read from a checkpoint, given the settings of `fresh` (the run's): refused unless it is one
    /// `end_episode` could have made (between episodes, every listed node stored once, links and
    /// frames sound, no more nodes than the capacity).
    pub fn restored(mut self, fresh: &Graph, frame_len: usize) -> Result<Graph, String> {
        self.cfg = fresh.cfg.clone();
        self.gamma = fresh.gamma;
        if !self.episode.is_empty() {
            return Err("graph: written during an episode".into());
        }
        if self.nodes.len() > self.cfg.nodes || self.order.len() != self.nodes.len() {
            return Err(format!(
                "graph: {} nodes, {} listed, capacity {}",
                self.nodes.len(),
                self.order.len(),
                self.cfg.nodes
            ));
        }
        // Counters that `+= 1` must never overflow: far beyond any run.
        const MAX_COUNT: u64 = 1 << 50;
        if self.next_id > MAX_COUNT || self.stamp > MAX_COUNT {
            return Err(format!(
                "graph: next id {} or stamp {} is out of range 0..={MAX_COUNT}",
                self.next_id, self.stamp
            ));
        }
        if self.last_sweeps > MAX_SWEEPS {
            return Err(format!("graph: last sweeps {} is out of range 0..={MAX_SWEEPS}", self.last_sweeps));
        }
        for id in &self.order {
            let node = self.nodes.get(id).ok_or_else(|| format!("graph: node {id} is listed but not stored"))?;
            let links = node.next.iter().all(|(k, &n)| {
                n < self.next_id
                    && match *k {
                        LinkKey::Action(a) => (a as usize) < ACTIONS,
                        LinkKey::Node(m) => m < self.next_id,
                    }
            });
            if !links {
                return Err(format!("graph: node {id} links to a node or by an action that never was"));
            }
            let sound = node.id == *id
                && *id < self.next_id
                && node.t <= u32::MAX as usize
                && (node.action as usize) < ACTIONS
                && node.state.len() == frame_len
                && node.next_state.len() == frame_len
                && node.rt.is_finite()
                && node.reward.is_finite()
                && node.embedding.iter().all(|x| x.is_finite());
            if !sound {
                return Err(format!("graph: node {id} is not sound"));
            }
            if self.by_bits.insert(node.embedding.map(f32::to_bits), *id).is_some() {
                return Err(format!("graph: node {id} repeats another's embedding"));
            }
            if node.stamp >= self.stamp || self.by_stamp.insert(node.stamp, *id).is_some() {
                return Err(format!("graph: node {id}'s stamp {} is not its own", node.stamp));
            }
        }
        Ok(self)
    }

    /// The most nodes it keeps (the least recently improved one is evicted past it).
    pub fn capacity(&self) -> usize {
        self.cfg.nodes
    }

    /// Whether it stores no node.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node `id`, if stored.
    pub fn node(&self, id: u64) -> Option<&Node> {
        self.nodes.get(&id)
    }

    /// The nodes in insertion order.
    pub fn ids(&self) -> &[u64] {
        &self.order
    }

    /// A transition of the episode in progress (added to the graph at its end).
    pub fn remember(&mut self, p: Pending) {
        self.episode.push(p);
    }

    /// The node for `e`: a stored one within the merge distance (in the tree of the nodes as
    /// they were before this episode), if any.
    fn merge_target(
        &self,
        tree: &Option<(ImmutableKdTree<f32, u32, EMBEDDING, 32>, Vec<u64>)>,
        e: &[f32; EMBEDDING],
    ) -> Option<u64> {
        let (tree, ids) = tree.as_ref()?;
        let nn = tree.nearest_one::<SquaredEuclidean>(e);
        let id = ids[nn.item as usize];
        let limit = (self.cfg.merge_distance * self.cfg.merge_distance) as f32;
        // The tree's squared distance, checked again exactly (the node may have been evicted).
        let node = self.nodes.get(&id)?;
        (nn.distance < limit && sq_dist(&node.embedding, e) < limit).then_some(id)
    }

    /// The episode's end: its transitions added backwards with discounted returns.
    pub fn end_episode(&mut self) {
        let episode = std::mem::take(&mut self.episode);
        let tree = (!self.nodes.is_empty()).then(|| {
            let ids: Vec<u64> = self.order.clone();
            let points: Vec<[f32; EMBEDDING]> = ids.iter().map(|id| self.nodes[id].embedding).collect();
            (ImmutableKdTree::new_from_slice(&points), ids)
        });
        let mut rt = 0.0f64;
        let mut previous: Option<u64> = None;
        for (t, p) in episode.into_iter().enumerate().rev() {
            rt = p.reward as f64 + self.gamma * rt;
            let merged = self.merge_target(&tree, &p.embedding);
            // An exact match of a node added during this episode (the authors' hash key) merges too.
            let key = merged.or_else(|| self.by_bits.get(&p.embedding.map(f32::to_bits)).copied());
            match key {
                Some(id) => {
                    let stamp = self.stamp;
                    let node = self.nodes.get_mut(&id).expect("listed");
                    if rt > node.rt {
                        node.rt = rt;
                        self.by_stamp.remove(&node.stamp);
                        self.by_stamp.insert(stamp, id);
                        node.stamp = stamp;
                        self.stamp += 1;
                    }
                    if let Some(prev) = previous {
                        node.next.insert(LinkKey::Action(p.action), prev);
                    }
                    previous = Some(id);
                }
                None => {
                    if self.nodes.len() < self.cfg.nodes {
                        let id = self.next_id;
                        self.next_id += 1;
                        let mut next = HashMap::new();
                        if let Some(prev) = previous {
                            next.insert(LinkKey::Action(p.action), prev);
                        }
                        let node = Node {
                            id,
                            embedding: p.embedding,
                            state: p.state,
                            next_state: p.next_state,
                            t,
                            action: p.action,
                            reward: p.reward,
                            done: p.done,
                            rt,
                            next,
                            stamp: self.stamp,
                        };
                        self.by_stamp.insert(self.stamp, id);
                        self.stamp += 1;
                        self.by_bits.insert(node.embedding.map(f32::to_bits), id);
                        self.nodes.insert(id, node);
                        self.order.push(id);
                        previous = Some(id);
                    }
                    if self.cfg.forgetting && self.nodes.len() >= self.cfg.nodes {
                        self.evict_lru();
                    }
                }
            }
        }
    }

    /// The authors' eviction: the node with the oldest stamp goes, and every node's links are
    /// re-keyed by the node they lead to, without the evicted one. A node whose links are already
    /// so keyed and skip the evicted node would be rebuilt as it is, so only the others are.
    fn evict_lru(&mut self) {
        #[cfg(test)]
        let expected = self.clone().evicted_by_scan();
        let Some((_, lru)) = self.by_stamp.pop_first() else { return };
        if let Some(node) = self.nodes.remove(&lru) {
            self.by_bits.remove(&node.embedding.map(f32::to_bits));
        }
        self.order.retain(|&id| id != lru);
        for node in self.nodes.values_mut() {
            if node.next.iter().any(|(k, &n)| matches!(k, LinkKey::Action(_)) || n == lru) {
                node.next = rekeyed(&node.next, lru);
            }
        }
        #[cfg(test)]
        assert_eq!(self.links(), expected.links(), "the same eviction as a scan of every node");
    }

    /// The eviction as the authors' code does it, a scan for the oldest stamp and a rebuild of
    /// every node's links: what `evict_lru` must equal.
    #[cfg(test)]
    fn evicted_by_scan(mut self) -> Graph {
        let Some(&lru) = self.order.iter().min_by_key(|id| self.nodes[id].stamp) else { return self };
        self.nodes.remove(&lru);
        self.order.retain(|&id| id != lru);
        for node in self.nodes.values_mut() {
            node.next = rekeyed(&node.next, lru);
        }
        self
    }

    /// Every node in order with its stamp, Rt and links (sorted), to compare two graphs.
    #[cfg(test)]
    fn links(&self) -> Vec<NodeLinks> {
        let key = |k: &LinkKey| match *k {
            LinkKey::Action(a) => (0, a as u64),
            LinkKey::Node(n) => (1, n),
        };
        self.order
            .iter()
            .map(|id| {
                let n = &self.nodes[id];
                let mut next: Vec<(LinkKey, u64)> = n.next.iter().map(|(k, v)| (*k, *v)).collect();
                next.sort_by_key(|(k, _)| key(k));
                (*id, n.stamp, n.rt.to_bits(), next)
            })
            .collect()
    }

    /// Value propagation after episode number `episodes` (1-based), every `propagateEvery`.
    pub fn propagate(&mut self, episodes: u64) {
        if episodes % self.cfg.propagate_every != 0 {
            return;
        }
        // Latest position in its episode first; equal positions in insertion order.
        let mut ids = self.order.clone();
        ids.sort_by_key(|id| std::cmp::Reverse(self.nodes[id].t));
        self.last_sweeps = 0;
        loop {
            let mut change = 0.0f64;
            for id in &ids {
                let node = &self.nodes[id];
                if node.done && !self.cfg.propagate_past_terminals {
                    continue;
                }
                let best = node
                    .next
                    .values()
                    .filter(|&&n| n != *id)
                    .filter_map(|n| self.nodes.get(n))
                    .map(|n| n.rt)
                    .fold(None, |b: Option<f64>, r| Some(b.map_or(r, |b| b.max(r))));
                if let Some(best) = best {
                    let update = node.reward as f64 + self.gamma * best;
                    let node = self.nodes.get_mut(id).expect("listed");
                    change += (update - node.rt).abs();
                    node.rt = update;
                }
            }
            self.last_sweeps += 1;
            if change <= self.cfg.converge || self.last_sweeps >= MAX_SWEEPS {
                break;
            }
        }
    }

    /// What its values rest on now (`Census`).
    pub fn census(&self) -> Census {
        let mut predecessors: HashMap<u64, Vec<u64>> = HashMap::new();
        for id in &self.order {
            for next in self.nodes[id].next.values() {
                predecessors.entry(*next).or_default().push(*id);
            }
        }
        let rewarded: Vec<u64> = self.order.iter().copied().filter(|id| self.nodes[id].reward > 0.0).collect();
        // Breadth first from the rewarded nodes, against the links.
        let mut hops: HashMap<u64, usize> = rewarded.iter().map(|&id| (id, 0)).collect();
        let mut queue: std::collections::VecDeque<u64> = rewarded.iter().copied().collect();
        while let Some(id) = queue.pop_front() {
            let d = hops[&id];
            for p in predecessors.get(&id).into_iter().flatten() {
                if !hops.contains_key(p) {
                    hops.insert(*p, d + 1);
                    queue.push_back(*p);
                }
            }
        }
        let mut values: Vec<f64> = self.order.iter().map(|&id| self.value(id)).collect();
        values.sort_by(f64::total_cmp);
        let mut hops: Vec<usize> = hops.into_values().collect();
        hops.sort_unstable();
        Census {
            nodes: self.order.len(),
            valued: self
                .order
                .iter()
                .filter(|id| self.nodes[id].next.contains_key(&LinkKey::Action(self.nodes[id].action)))
                .count(),
            rewarded: rewarded.len(),
            rewarded_linked: rewarded
                .iter()
                .filter(|id| self.nodes[id].done && !self.nodes[id].next.is_empty())
                .count(),
            max_reward: rewarded.iter().map(|id| self.nodes[id].reward as f64).fold(0.0, f64::max),
            values,
            hops,
        }
    }

    /// `n` node ids drawn uniformly with replacement, from the nodes in insertion order.
    pub fn sample(&self, n: usize, rng: &mut ChaCha8Rng) -> Vec<u64> {
        (0..n).map(|_| self.order[rng.gen_range(0..self.order.len() as u32) as usize]).collect()
    }

    /// The graph's value of a node: Rt of the node its own action led to, 0 without that link.
    pub fn value(&self, id: u64) -> f64 {
        let node = &self.nodes[&id];
        node.next.get(&LinkKey::Action(node.action)).and_then(|n| self.nodes.get(n)).map_or(0.0, |n| n.rt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    /// Episodes of states on a line, spaced so that some merge, some repeat and some are new,
    /// into a small graph that evicts at nearly every new node: each eviction is checked against
    /// the scan (`evict_lru`), and the graph must survive a checkpoint's round trip.
    #[test]
    fn eviction_by_stamp_index_equals_the_authors_scan() {
        let cfg = ErlamConfig { nodes: 40, ..ErlamConfig::default() };
        let mut g = Graph::new(cfg, 0.9);
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for episode in 1..=120u64 {
            let len = rng.gen_range(3..20);
            for t in 0..len {
                let mut embedding = [0.0f32; EMBEDDING];
                embedding[0] = rng.gen_range(0..200u32) as f32 * 0.015;
                embedding[1] = (episode % 3) as f32;
                let done = t + 1 == len;
                let reward = if done && rng.gen_bool(0.4) { 1.0 } else { -0.01 };
                let p =
                    Pending { embedding, state: vec![], next_state: vec![], action: rng.gen_range(0..9), reward, done };
                g.remember(p);
            }
            g.end_episode();
            g.propagate(episode);
            assert!(g.len() < 40);
        }
        assert!(g.next_id as usize - g.len() > 300, "evicted {} times", g.next_id as usize - g.len());
        let round_trip = |g: &Graph| {
            let mut bytes = Vec::new();
            ciborium::into_writer(g, &mut bytes).unwrap();
            ciborium::from_reader::<Graph, _>(bytes.as_slice()).unwrap().restored(&Graph::new(g.cfg.clone(), 0.9), 0)
        };
        assert_eq!(round_trip(&g).unwrap().by_stamp, g.by_stamp, "the index is rebuilt from the stamps");
        let mut shared = g.clone();
        let stamp = shared.nodes[&shared.order[0]].stamp;
        let second = shared.order[1];
        shared.nodes.get_mut(&second).unwrap().stamp = stamp;
        assert!(round_trip(&shared).unwrap_err().contains("stamp"), "two nodes with one stamp are refused");
    }
}
