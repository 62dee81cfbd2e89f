//! [`Cache`]: the structures a design analysed, least recently used first out, bounded by the
//! memory they hold.

use std::collections::HashMap;
use std::hash::Hash;
use std::sync::Arc;

/// A map from keys to shared values that holds at most `budget` bytes (as each insertion
/// states them), evicting the least recently used entries; the entry inserted last is kept
/// whatever its size.
#[derive(Debug)]
pub struct Cache<K, V> {
    entries: HashMap<K, Entry<V>>,
    budget: usize,
    bytes: usize,
    clock: u64,
}

#[derive(Debug)]
struct Entry<V> {
    value: Arc<V>,
    bytes: usize,
    used: u64,
}

impl<K: Hash + Eq + Clone, V> Cache<K, V> {
    /// An empty cache of at most `budget` bytes.
    pub fn new(budget: usize) -> Self {
        Cache {
            entries: HashMap::new(),
            budget,
            bytes: 0,
            clock: 0,
        }
    }

    /// The value of `key`, marked as just used.
    pub fn get(&mut self, key: &K) -> Option<Arc<V>> {
        self.clock += 1;
        let e = self.entries.get_mut(key)?;
        e.used = self.clock;
        Some(e.value.clone())
    }

    /// Stores `value` of `bytes` bytes under `key`, then evicts the least recently used
    /// other entries while the total is over the budget.
    pub fn insert(&mut self, key: K, value: Arc<V>, bytes: usize) {
        self.clock += 1;
        let entry = Entry {
            value,
            bytes,
            used: self.clock,
        };
        if let Some(old) = self.entries.insert(key.clone(), entry) {
            self.bytes -= old.bytes;
        }
        self.bytes += bytes;
        while self.bytes > self.budget && self.entries.len() > 1 {
            let oldest = self
                .entries
                .iter()
                .filter(|(k, _)| **k != key)
                .min_by_key(|(_, e)| e.used)
                .map(|(k, _)| k.clone());
            let Some(oldest) = oldest else { break };
            if let Some(e) = self.entries.remove(&oldest) {
                self.bytes -= e.bytes;
            }
        }
    }

    /// Every value held, in no particular order (not marked as used).
    pub fn values(&self) -> impl Iterator<Item = &Arc<V>> {
        self.entries.values().map(|e| &e.value)
    }

    /// Entries held.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether it holds nothing.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.bytes
    }
}

#[cfg(test)]
mod tests {
    use super::Cache;
    use std::sync::Arc;

    #[test]
    fn the_least_recently_used_go_first_and_the_budget_holds() {
        let mut c = Cache::new(30);
        c.insert(1, Arc::new("a"), 10);
        c.insert(2, Arc::new("b"), 10);
        c.insert(3, Arc::new("c"), 10);
        assert_eq!(c.get(&1).as_deref(), Some(&"a"));
        c.insert(4, Arc::new("d"), 10);
        // 2 was used least recently.
        assert!(c.get(&2).is_none());
        assert_eq!((c.len(), c.bytes()), (3, 30));
        for k in [1, 3, 4] {
            assert!(c.get(&k).is_some(), "{k}");
        }
        // An entry larger than the budget is kept alone.
        c.insert(5, Arc::new("e"), 100);
        assert_eq!((c.len(), c.bytes()), (1, 100));
        assert!(c.get(&5).is_some());
        // Replacing a key counts its bytes once.
        c.insert(5, Arc::new("f"), 20);
        assert_eq!((c.len(), c.bytes()), (1, 20));
    }
}
