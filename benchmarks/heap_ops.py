"""The cost of one binary-heap operation in the core's pattern, in numba, and its variants.

The "hold" pattern: the top entry is filed again an exponential time later;
positions written into 104-byte rows (as book's HEAP_POS) or 8-byte ones.
usage: heap_ops.py (prints ns per operation at N = 1e4, 1e5, 1e6)
"""

import numpy as np
import time
from numba import njit


@njit(inline="always")
def less(t1, k1, t2, k2):
    return t1 < t2 or (t1 == t2 and k1 < k2)


@njit
def bin_std(heap, ht, hk, pos, m, rng_t, rng_k):
    n = heap.shape[0]
    for s in range(m):
        k = 0
        i = heap[0]
        t = ht[0] + rng_t[s]
        key = rng_k[s]
        while True:
            child = 2 * k + 1
            if child >= n:
                break
            tc, kc = ht[child], hk[child]
            if child + 1 < n:
                t2, k2 = ht[child + 1], hk[child + 1]
                if t2 < tc or (t2 == tc and k2 < kc):
                    child += 1
                    tc, kc = t2, k2
            if tc < t or (tc == t and kc < key):
                jc = heap[child]
                heap[k], ht[k], hk[k] = jc, tc, kc
                pos[jc * 13] = k
                k = child
            else:
                break
        heap[k], ht[k], hk[k] = i, t, key
        pos[i * 13] = k


@njit
def bin_floyd(heap, ht, hk, pos, m, rng_t, rng_k):
    n = heap.shape[0]
    for s in range(m):
        k = 0
        i = heap[0]
        t = ht[0] + rng_t[s]
        key = rng_k[s]
        while True:
            child = 2 * k + 1
            if child >= n:
                break
            if child + 1 < n:
                t1 = ht[child]
                t2 = ht[child + 1]
                if t2 < t1 or (t2 == t1 and hk[child + 1] < hk[child]):
                    child += 1
            jc = heap[child]
            heap[k], ht[k], hk[k] = jc, ht[child], hk[child]
            pos[jc * 13] = k
            k = child
        while k > 0:
            p = (k - 1) >> 1
            tp = ht[p]
            if t < tp or (t == tp and key < hk[p]):
                jp = heap[p]
                heap[k], ht[k], hk[k] = jp, tp, hk[p]
                pos[jp * 13] = k
                k = p
            else:
                break
        heap[k], ht[k], hk[k] = i, t, key
        pos[i * 13] = k


@njit
def quad_floyd(heap, ht, hk, pos, m, rng_t, rng_k):
    n = heap.shape[0]
    for s in range(m):
        k = 0
        i = heap[0]
        t = ht[0] + rng_t[s]
        key = rng_k[s]
        while True:
            c = 4 * k + 1
            if c >= n:
                break
            best = c
            tb = ht[c]
            kb = hk[c]
            e = c + 4 if c + 4 <= n else n
            for q in range(c + 1, e):
                tq = ht[q]
                if tq < tb or (tq == tb and hk[q] < kb):
                    best = q
                    tb = tq
                    kb = hk[q]
            jc = heap[best]
            heap[k], ht[k], hk[k] = jc, tb, kb
            pos[jc * 13] = k
            k = best
        while k > 0:
            p = (k - 1) >> 2
            tp = ht[p]
            if t < tp or (t == tp and key < hk[p]):
                jp = heap[p]
                heap[k], ht[k], hk[k] = jp, tp, hk[p]
                pos[jp * 13] = k
                k = p
            else:
                break
        heap[k], ht[k], hk[k] = i, t, key
        pos[i * 13] = k


@njit
def quad_std(heap, ht, hk, pos, m, rng_t, rng_k):
    n = heap.shape[0]
    for s in range(m):
        k = 0
        i = heap[0]
        t = ht[0] + rng_t[s]
        key = rng_k[s]
        while True:
            c = 4 * k + 1
            if c >= n:
                break
            best = c
            tb = ht[c]
            kb = hk[c]
            e = c + 4 if c + 4 <= n else n
            for q in range(c + 1, e):
                tq = ht[q]
                if tq < tb or (tq == tb and hk[q] < kb):
                    best = q
                    tb = tq
                    kb = hk[q]
            if tb < t or (tb == t and kb < key):
                jc = heap[best]
                heap[k], ht[k], hk[k] = jc, tb, kb
                pos[jc * 13] = k
                k = best
            else:
                break
        heap[k], ht[k], hk[k] = i, t, key
        pos[i * 13] = k


for n in (10000, 100000, 1000000):
    m = 2000000
    rng = np.random.default_rng(1)
    rt = rng.exponential(1.0, m)
    rk = rng.integers(0, 1 << 40, m)
    res = {}
    for name, f in (
        ("bin_std", bin_std),
        ("bin_floyd", bin_floyd),
        ("quad_std", quad_std),
        ("quad_floyd", quad_floyd),
    ):
        ts = []
        for _rep in range(3):
            heap = np.arange(n)
            ht = np.sort(rng.exponential(1.0, n))
            hk = rng.integers(0, 1 << 40, n)
            pos = np.zeros(n * 13, np.int64)
            f(heap, ht, hk, pos, 1000, rt, rk)
            c0 = time.process_time()
            f(heap, ht, hk, pos, m, rt, rk)
            ts.append((time.process_time() - c0) / m * 1e9)
        print(n, name, " ".join(f"{x:.1f}" for x in ts), "ns/op", flush=True)
