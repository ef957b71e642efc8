use mechgen::sixbar::Sixbar;
fn main() {
    let m = Sixbar::<f64>::default();
    let (x, q) = Sixbar::<f64>::start();
    let mut q = q.to_array();
    let mut x = x.to_array();
    let o = mechgen::NewtonOptions::default();
    m.solve_position(&x, &mut q, &o).unwrap();
    for _ in 0..5 {
        x[0] += 1f64.to_radians();
        let r = m.solve_position(&x, &mut q, &o).unwrap();
        println!("{:?}", r);
    }
    let t = std::time::Instant::now();
    let mut s = 0.0;
    for i in 0..10_000_000 {
        let v = (i as f64) * 1e-3;
        let (a, b) = std::hint::black_box(v).sin_cos();
        s += a + b;
    }
    println!("sin_cos {:?} ns {}", t.elapsed().as_nanos() as f64 / 1e7, s);
}
