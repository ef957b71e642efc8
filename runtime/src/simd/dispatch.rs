//! The widest vector instructions of the CPU, chosen at run time: [`dispatch`] runs a [`Kernel`]
//! compiled for AVX-512, for AVX2 and for baseline x86-64, whichever the CPU has (by `pulp`,
//! which keeps the `unsafe` of calling a function with target features in one audited crate).
//! Lane code over [`Vf64`](super::Vf64) / [`Vf32`](super::Vf32) inlined into a kernel's `run`
//! takes those instructions; the results are the same bit for bit on every path.

/// The most unknowns a mechanism may have for [`Isa::f64_lanes_for`] to give eight lanes.
pub const EIGHT_LANES_UP_TO: usize = 4;

/// Work to run with the CPU's widest vectors. `run` should be `#[inline(always)]`, and so should
/// what it calls on its fast path, so that it is compiled inside each instruction set's copy
/// (every lane tick generated code emits, and the runtime's lane kernels, are).
pub trait Kernel {
    type Output;
    fn run(self) -> Self::Output;
}

/// An instruction set [`dispatch_on`] can run kernels with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Isa {
    /// The build's own target features (SSE2 on baseline x86-64; anything on other CPUs).
    Baseline,
    /// x86-64-v3: AVX2, FMA, BMI1/2 (fused multiply-add is never contracted into: Rust does not).
    Avx2,
    /// x86-64-v4: AVX-512 F, BW, CD, DQ, VL.
    Avx512,
}

impl Isa {
    /// Every instruction set, narrowest first.
    pub const ALL: [Isa; 3] = [Isa::Baseline, Isa::Avx2, Isa::Avx512];

    /// The widest instruction set this CPU has.
    pub fn widest() -> Isa {
        Isa::ALL
            .into_iter()
            .rev()
            .find(|isa| isa.available())
            .unwrap_or(Isa::Baseline)
    }

    /// Whether this CPU runs kernels with `self`.
    pub fn available(self) -> bool {
        self.arch().is_some()
    }

    /// The f64 lanes a group of instances runs fastest in per instance with `self`: eight with
    /// AVX-512 (one register), four otherwise. Measured on an AMD EPYC with AVX2 (2026-11-29,
    /// `docs/speed.md`): a six-bar's lane tick per instance 53 ns in four lanes against 66 ns in
    /// eight (two registers each, twice the spills); on baseline SSE2, 95 ns in four or two, 133
    /// ns in eight.
    pub fn f64_lanes(self) -> usize {
        match self {
            Isa::Avx512 => 8,
            Isa::Baseline | Isa::Avx2 => 4,
        }
    }

    /// [`Isa::f64_lanes`] for a mechanism of `unknowns` unknowns: four for one of more than
    /// [`EIGHT_LANES_UP_TO`] unknowns, whose lane tick runs faster per set in four lanes than in
    /// eight even with AVX-512. Measured on an Intel Xeon (Emerald Rapids) with AVX-512
    /// (2026-11-30, `mechgen batch`, `docs/speed.md`): Strandbeest legs of 6, 8 and 10 unknowns
    /// 7–30 % faster in four lanes; the four-bar (2) and the six-bar (4) 4–10 % faster in eight.
    pub fn f64_lanes_for(self, unknowns: usize) -> usize {
        if unknowns > EIGHT_LANES_UP_TO {
            self.f64_lanes().min(4)
        } else {
            self.f64_lanes()
        }
    }

    /// `baseline`, `avx2` or `avx512`.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Baseline => "baseline",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
        }
    }

    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    fn arch(self) -> Option<pulp::Arch> {
        use pulp::x86::{V3, V4};
        match self {
            Isa::Baseline => Some(pulp::Arch::Scalar),
            Isa::Avx2 => V3::try_new().map(pulp::Arch::V3),
            Isa::Avx512 => V4::try_new().map(pulp::Arch::V4),
        }
    }

    #[cfg(not(all(feature = "std", target_arch = "x86_64")))]
    fn arch(self) -> Option<()> {
        (self == Isa::Baseline).then_some(())
    }
}

/// Runs `kernel` with the widest instruction set of this CPU ([`Isa::widest`]).
#[inline(always)]
pub fn dispatch<K: Kernel>(kernel: K) -> K::Output {
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    {
        // Detected once (pulp asks the CPU on every `Arch::new`).
        static ARCH: std::sync::OnceLock<pulp::Arch> = std::sync::OnceLock::new();
        ARCH.get_or_init(pulp::Arch::new).dispatch(Op(kernel))
    }
    #[cfg(not(all(feature = "std", target_arch = "x86_64")))]
    {
        kernel.run()
    }
}

/// Runs `kernel` with `isa`, or gives it back where this CPU does not have `isa`.
#[inline(always)]
pub fn dispatch_on<K: Kernel>(isa: Isa, kernel: K) -> Result<K::Output, K> {
    match isa.arch() {
        #[cfg(all(feature = "std", target_arch = "x86_64"))]
        Some(arch) => Ok(arch.dispatch(Op(kernel))),
        #[cfg(not(all(feature = "std", target_arch = "x86_64")))]
        Some(()) => Ok(kernel.run()),
        None => Err(kernel),
    }
}

/// A kernel as pulp's operation: `with_simd` inlined into each instruction set's copy.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
struct Op<K>(K);

#[cfg(all(feature = "std", target_arch = "x86_64"))]
impl<K: Kernel> pulp::WithSimd for Op<K> {
    type Output = K::Output;
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> K::Output {
        self.0.run()
    }
}
