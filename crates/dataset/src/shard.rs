//! Shards of a study: process K of N renders the pairs with index % N == K (`--shard K/N`).

/// Which part of the study this process renders: pairs with `index % count == shard`.
#[derive(Debug, Clone, Copy)]
pub struct Shard {
    pub shard: usize,
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = String;

    /// `K/N`: the K-th of N shards, 0 <= K < N.
    fn from_str(text: &str) -> Result<Self, String> {
        text.split_once('/')
            .and_then(|(k, n)| Some((k.parse::<usize>().ok()?, n.parse::<usize>().ok()?)))
            .filter(|&(k, n)| n > 0 && k < n)
            .map(|(shard, count)| Shard { shard, count })
            .ok_or_else(|| "must be K/N with 0 <= K < N".to_string())
    }
}

/// Indices of the pairs a shard renders (every pair in exactly one shard).
pub fn shard_indices(total: usize, shard: Shard) -> Vec<usize> {
    (0..total).filter(|i| i % shard.count == shard.shard).collect()
}
