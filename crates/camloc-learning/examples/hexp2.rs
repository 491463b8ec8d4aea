use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};
use rayon::prelude::*;
use std::time::Instant;

struct P { n: usize, dd: usize, kk: usize, x: Vec<f64>, p: Vec<f64>, pairs: Vec<(usize,usize)>, fp: Vec<(usize,usize)> }

fn build(pr: &P, i0: usize, c: usize, u: &mut [f64], w: &mut [f64]) {
    let n = pr.n;
    for (col, &(a, b)) in u.chunks_exact_mut(c).zip(&pr.fp) {
        let xa = &pr.x[a * n + i0..a * n + i0 + c];
        let xb = &pr.x[b * n + i0..b * n + i0 + c];
        for ((o, &va), &vb) in col.iter_mut().zip(xa).zip(xb) { *o = va * vb; }
    }
    let rp = &pr.p[i0 * pr.kk..(i0 + c) * pr.kk];
    for (col, &(j, l)) in w.chunks_exact_mut(c).zip(&pr.pairs) {
        for (o, p) in col.iter_mut().zip(rp.chunks_exact(pr.kk)) { *o = p[j] * p[l]; }
    }
}

fn run(pr: &P, c: usize, transposed: bool, nw: usize) -> f64 {
    let tt = pr.fp.len(); let qq = pr.pairs.len(); let n = pr.n;
    let mut bufs: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (0..nw).map(|_| (vec![0.0; c * tt], vec![0.0; c * qq], vec![0.0; qq * tt])).collect();
    let t0 = Instant::now();
    let per = n.div_ceil(nw);
    let par = if nw == 1 { Par::rayon(0) } else { Par::Seq };
    bufs.par_iter_mut().enumerate().for_each(|(wi, (u, w, acc))| {
        let lo = wi * per; let hi = ((wi + 1) * per).min(n);
        let mut i0 = lo;
        while i0 < hi {
            let cc = c.min(hi - i0);
            build(pr, i0, cc, &mut u[..cc * tt], &mut w[..cc * qq]);
            let uv = MatRef::from_column_major_slice(&u[..cc * tt], cc, tt);
            let wv = MatRef::from_column_major_slice(&w[..cc * qq], cc, qq);
            if transposed {
                matmul(MatMut::from_column_major_slice_mut(acc, tt, qq), Accum::Add, uv.transpose(), wv, 1.0, par);
            } else {
                matmul(MatMut::from_column_major_slice_mut(acc, qq, tt), Accum::Add, wv.transpose(), uv, 1.0, par);
            }
            i0 += cc;
        }
    });
    t0.elapsed().as_secs_f64()
}

fn main() {
    let n = 43188; let dd = 75; let kk = 12;
    let fp: Vec<(usize,usize)> = (0..dd).flat_map(|a| (a..dd).map(move |b| (a, b))).collect();
    let pairs: Vec<(usize,usize)> = (0..kk).flat_map(|j| (j + 1..kk).map(move |l| (j, l))).collect();
    let x: Vec<f64> = (0..n * dd).map(|i| ((i * 7919 % 1000) as f64) / 1000.0 - 0.5).collect();
    let p: Vec<f64> = (0..n * kk).map(|i| ((i * 104729 % 1000) as f64) / 12000.0).collect();
    let pr = P { n, dd, kk, x, p, pairs, fp };
    let flops = 2.0 * n as f64 * pr.fp.len() as f64 * pr.pairs.len() as f64;
    let variants: Vec<(usize, bool, usize)> = vec![(128,false,2),(256,false,2),(384,false,2),(512,false,2),(256,true,2),(512,true,2),(256,false,1),(1024,false,1)];
    let mut best = vec![f64::INFINITY; variants.len()];
    let a = faer::Mat::<f64>::from_fn(2048, 2048, |i, j| (i + j) as f64 * 1e-3);
    let mut cm = faer::Mat::<f64>::zeros(2048, 2048);
    let mut gbest = [f64::INFINITY; 2];
    for _round in 0..4 {
        for (vi, &(c, tr, nw)) in variants.iter().enumerate() { best[vi] = best[vi].min(run(&pr, c, tr, nw)); }
        for (gi, par) in [Par::Seq, Par::rayon(0)].into_iter().enumerate() {
            let t = Instant::now(); matmul(cm.as_mut(), Accum::Replace, a.as_ref(), a.as_ref(), 1.0, par); gbest[gi] = gbest[gi].min(t.elapsed().as_secs_f64());
        }
    }
    for (vi, &(c, tr, nw)) in variants.iter().enumerate() {
        eprintln!("chunk {c} transposed {tr} workers {nw}: {:.3}s {:.1} GF/s", best[vi], flops / best[vi] / 1e9);
    }
    eprintln!("gemm seq {:.1} par {:.1}", 2.0*2048f64.powi(3)/gbest[0]/1e9, 2.0*2048f64.powi(3)/gbest[1]/1e9);
}
