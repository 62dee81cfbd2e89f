//! Dinic's maximum flow, for the ratio bound's max-weight closures. Hand-written: the
//! graphs are tiny (a node per free curve and per group of shared vertices) and solved
//! thousands of times per certificate; a general graph library would cost more in setup
//! than the flow itself.

/// Dinic's maximum flow on a small graph with `f64` capacities.
pub(super) struct Dinic {
    adj: Vec<Vec<usize>>,
    to: Vec<usize>,
    cap: Vec<f64>,
}

impl Dinic {
    pub(super) fn new(n: usize) -> Self {
        Dinic {
            adj: vec![Vec::new(); n],
            to: Vec::new(),
            cap: Vec::new(),
        }
    }

    pub(super) fn add(&mut self, u: usize, v: usize, c: f64) {
        self.adj[u].push(self.to.len());
        self.to.push(v);
        self.cap.push(c);
        self.adj[v].push(self.to.len());
        self.to.push(u);
        self.cap.push(0.0);
    }

    fn levels(&self, s: usize, eps: f64) -> Vec<usize> {
        let mut level = vec![usize::MAX; self.adj.len()];
        level[s] = 0;
        let mut queue = std::collections::VecDeque::from([s]);
        while let Some(u) = queue.pop_front() {
            for &e in &self.adj[u] {
                let v = self.to[e];
                if self.cap[e] > eps && level[v] == usize::MAX {
                    level[v] = level[u] + 1;
                    queue.push_back(v);
                }
            }
        }
        level
    }

    fn push(
        &mut self,
        u: usize,
        t: usize,
        f: f64,
        level: &[usize],
        it: &mut [usize],
        eps: f64,
    ) -> f64 {
        if u == t {
            return f;
        }
        while it[u] < self.adj[u].len() {
            let e = self.adj[u][it[u]];
            let v = self.to[e];
            if self.cap[e] > eps && level[v] == level[u].wrapping_add(1) {
                let d = self.push(v, t, f.min(self.cap[e]), level, it, eps);
                if d > 0.0 {
                    self.cap[e] -= d;
                    self.cap[e ^ 1] += d;
                    return d;
                }
            }
            it[u] += 1;
        }
        0.0
    }

    pub(super) fn max_flow(&mut self, s: usize, t: usize, eps: f64) -> f64 {
        let mut flow = 0.0;
        loop {
            let level = self.levels(s, eps);
            if level[t] == usize::MAX {
                return flow;
            }
            let mut it = vec![0; self.adj.len()];
            loop {
                let f = self.push(s, t, f64::INFINITY, &level, &mut it, eps);
                if !(f > eps) {
                    if f > 0.0 {
                        flow += f;
                    }
                    break;
                }
                flow += f;
            }
        }
    }

    pub(super) fn reachable(&self, s: usize, eps: f64) -> Vec<bool> {
        let level = self.levels(s, eps);
        level.iter().map(|&l| l != usize::MAX).collect()
    }
}
