//! Sets of one generated mechanism swept side by side in SIMD lanes (what `batch` runs): each
//! set is walked to its start row by the scalar sweep (`rows.rs`), then the sets' rows above it
//! are ticked together, one lane per set, at the CPU's widest vectors. A lane tick is its scalar
//! tick bit for bit, and every substep is held to the same branch rule and every row to the same
//! condition bound as the scalar walk (`walker.rs`), so a lane's rows are the scalar sweep's rows.
//! A set whose walk needs more than the tick (a substep the rule refuses, a row near a singular
//! point, a failed row, the budget spent) leaves the lanes: its caller sweeps it again with the
//! scalar sweep, whose rows then replace the lane's. Part of [`crate::sweep`].

use super::route::Route;
use super::rows::{First, walk_to_first};
use super::walker::RESOLVE_CONDITION;
use super::{Continuation, Row, RowRef, Solved};
use mechgen_runtime::simd::Vf64;
use mechgen_runtime::{
    DynMechanism, InputMotion, LaneMechanism, LaneView, Lanes, PointMotion, StaticMechanism,
};

/// The most sets one group sweeps: eight f64 lanes (one AVX-512 vector).
pub const LANES: usize = <Vf64<8> as Lanes>::W;

/// Fewer sets than this are left to the scalar sweep. Two sets already gain: a four-lane tick
/// costs 1.3 scalar ticks with AVX2 (`docs/speed.md`).
pub const MIN_LANES: usize = 2;

/// Sweeps the sets `mechs` (at most [`LANES`], at least [`MIN_LANES`]; each a mechanism with its
/// set's params; up to four in four lanes, more in eight) as
/// [`super::sweep_each_with`] sweeps each (input `index` over `values`, rate `rate`, `held` inputs
/// moved first), handing set `i`'s row `r` (its index in `values`) to `emit(i, r, row)` as the
/// walk solves it: the start row (by the scalar walk), the rows below it downward, then those
/// above it upward (the last two in the lanes). Returns the sets (a bit
/// each) whose sweep left the lanes: the rows handed out for them are to be dropped and the set
/// swept by the scalar sweep (with its branch oracle, for the statuses of failed rows).
#[allow(clippy::too_many_arguments)]
pub fn sweep_sets_in_lanes<M: StaticMechanism<f64>>(
    mechs: &[M],
    index: usize,
    values: &[f64],
    rate: f64,
    held: &[(usize, f64)],
    c: &Continuation,
    emit: &mut dyn FnMut(usize, usize, RowRef<'_>),
) -> u32 {
    let walk = (index, values, rate, held, c);
    if mechs.len() <= 4 {
        sweep_in::<M, Vf64<4>>(mechs, walk, emit)
    } else {
        sweep_in::<M, Vf64<8>>(mechs, walk, emit)
    }
}

/// What every set's sweep is: the input swept, its values and rate, the inputs held, the
/// continuation.
type SweepOf<'a> = (usize, &'a [f64], f64, &'a [(usize, f64)], &'a Continuation);

/// [`sweep_sets_in_lanes`] in the lanes `L`.
fn sweep_in<M: StaticMechanism<f64>, L: Lanes<Scalar = f64>>(
    mechs: &[M],
    (index, values, rate, held, c): SweepOf<'_>,
    emit: &mut dyn FnMut(usize, usize, RowRef<'_>),
) -> u32 {
    let n = mechs.len().min(L::W);
    let all = if n == 32 { u32::MAX } else { (1u32 << n) - 1 };
    if n < MIN_LANES || mechs.len() > L::W {
        return all;
    }
    let dyns: Vec<&dyn DynMechanism<f64>> =
        mechs.iter().map(|m| m as &dyn DynMechanism<f64>).collect();
    let Some(info) = dyns.first().map(|k| k.info_ref()) else {
        return all;
    };
    // Each set to its start row, by the scalar walk.
    let mut leave = 0u32;
    let mut firsts: Vec<Option<First<'_>>> = Vec::with_capacity(n);
    for (i, k) in dyns.iter().enumerate() {
        let mut failed = false;
        let mut row_of_set = |r: usize, row: RowRef<'_>| {
            failed |= row.result.is_err();
            emit(i, r, row);
        };
        let rows = (&mut row_of_set as &mut dyn FnMut(usize, RowRef<'_>), false);
        // The start row only: the lanes walk down from it, then up.
        let first = walk_to_first(*k, &info, index, values, rate, held, c, None, rows, false);
        // A failed row's status needs the branch oracle the scalar sweep is given.
        if failed {
            leave |= 1 << i;
        }
        firsts.push(first.filter(|f| f.solved));
    }
    let mut walks = Vec::with_capacity(n);
    for (i, f) in firsts.iter().enumerate() {
        let lane = f.as_ref().and_then(|f| {
            let (x, q) = f.at_first.state()?;
            Some((x, q, f.walker.lane_walk()?, f.after_down))
        });
        match lane {
            Some(l) if leave >> i & 1 == 0 => walks.push(Some(l)),
            _ => {
                // Not for the lanes (its rows past the start row are the scalar sweep's).
                if f.is_some() || firsts[i].is_none() && values.len() > 1 {
                    leave |= 1 << i;
                }
                walks.push(None);
            }
        }
    }
    let Some((lead, (x0, _, w0, _))) = walks
        .iter()
        .enumerate()
        .find_map(|(i, w)| w.map(|w| (i, w)))
    else {
        return leave;
    };
    // The lanes walk one input sequence in one substep sequence under one branch rule: the same
    // inputs, rates and largest substep for every set, and guards that differ in their length
    // scale at most.
    for (i, w) in walks.iter_mut().enumerate() {
        if let Some((x, _, lw, _)) = w
            && (*x != x0
                || lw.xd != w0.xd
                || lw.xdd != w0.xdd
                || lw.h_max != w0.h_max
                || !lw.guard.same_kinds(w0.guard))
        {
            *w = None;
            leave |= 1 << i;
        }
    }
    let first = firsts[lead].as_ref().map_or(0, |f| f.nearest);
    let active: u32 = (0..n)
        .filter(|&i| walks[i].is_some())
        .fold(0, |m, i| m | 1 << i);
    if values.len() <= 1 {
        return leave;
    }
    let lane_of = |i: usize| if walks[i].is_some() { i } else { lead };
    let group =
        <M::Lanes<L> as LaneMechanism<L>>::from_fn(|i| mechs[lane_of(i.min(n - 1))].clone());
    let mut run = Run::<M, L> {
        group,
        tick: None,
        x: x0.to_vec(),
        xd: w0.xd.to_vec(),
        xdd: w0.xdd.to_vec(),
        allowance: [0; LANES],
        active,
        nu: info.unknowns.len(),
        before: vec![L::splat(0.0); 3 * info.unknowns.len()],
        q: vec![0.0; L::W * info.unknowns.len()],
        qd: vec![0.0; L::W * info.unknowns.len()],
        qdd: vec![0.0; L::W * info.unknowns.len()],
        points: vec![PointMotion::default(); L::W * info.points.len()],
        np: info.points.len(),
    };
    let mut guess = vec![0.0; L::W * run.nu];
    for lane in 0..L::W {
        let i = lane_of(lane.min(n - 1));
        if let Some((_, q, _, after_down)) = &walks[i] {
            guess[lane * run.nu..(lane + 1) * run.nu].copy_from_slice(q);
            run.allowance[lane] = *after_down;
        }
    }
    let scales = L::from_fn(|lane| {
        let i = lane_of(lane.min(n - 1));
        walks[i].as_ref().map_or(1.0, |w| w.2.guard.scale())
    });
    let guard = (w0.guard, scales);
    // Down from the start row, then up from it again, as the scalar walk goes: the tick started
    // afresh at the start row both times and every SEGMENT rows on; the budget of each lane
    // carried from the rows below to those above.
    let walk = (values, index, w0.h_max);
    run.start(&guess, c);
    run.walk((0..first).rev(), walk, c, guard, emit);
    if first > 0 && first + 1 < values.len() {
        run.x.copy_from_slice(x0);
        run.start(&guess, c);
    }
    run.walk(first + 1..values.len(), walk, c, guard, emit);
    leave | (active & !run.active)
}

/// A lane tick and the branch rule on its lanes as one kernel, both compiled with the CPU's
/// widest vectors (the rule run apart from the tick ran on the build's baseline vectors: a
/// quarter of the instructions of a Strandbeest leg's lane tick). Gives the bits of the lanes
/// whose tick succeeded and whose step the rule keeps.
struct GuardedTick<'a, L: Lanes<Scalar = f64>, G: LaneMechanism<L>> {
    group: &'a G,
    t: &'a mut G::Tick,
    input: &'a InputMotion<G::X>,
    options: &'a mechgen_runtime::SolveOptions<f64>,
    rule: (&'a mechgen_runtime::guard::BranchGuard, L),
    /// The unknowns, their rates and accelerations before the tick.
    before: &'a [L],
    dt: f64,
}

impl<L: Lanes<Scalar = f64>, G: LaneMechanism<L>> mechgen_runtime::simd::Kernel
    for GuardedTick<'_, L, G>
{
    type Output = u32;
    #[inline(always)]
    fn run(self) -> u32 {
        self.group.tick(self.t, self.input, self.options);
        let (b, (guard, scales)) = (self.before, self.rule);
        let q_now = self.t.lanes_q().0;
        let nu = q_now.len();
        if b.len() != 3 * nu {
            return 0;
        }
        let kept = guard.keeps_lanes(
            scales,
            &b[..nu],
            &b[nu..2 * nu],
            &b[2 * nu..],
            self.dt,
            q_now,
        );
        kept & self.t.ok_bits()
    }
}

/// The lane walk: the group and its tick, the inputs all lanes share, each lane's budget and
/// whether it is still in the lanes, and buffers for one lane's numbers.
struct Run<M: StaticMechanism<f64>, L: Lanes<Scalar = f64>> {
    group: M::Lanes<L>,
    tick: Option<<M::Lanes<L> as LaneMechanism<L>>::Tick>,
    x: Vec<f64>,
    xd: Vec<f64>,
    xdd: Vec<f64>,
    /// Lane `i`'s budget in entry `i` (of the first `L::W`).
    allowance: [usize; LANES],
    active: u32,
    nu: usize,
    /// The unknowns, rates and accelerations before the last substep, in lanes.
    before: Vec<L>,
    /// Every lane's numbers of the last row (lane after lane).
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    points: Vec<PointMotion<f64>>,
    np: usize,
}

impl<M: StaticMechanism<f64>, L: Lanes<Scalar = f64>> Run<M, L> {
    /// The shared inputs as lanes.
    fn input(&self) -> InputMotion<<M::Lanes<L> as LaneMechanism<L>>::X> {
        let lanes = |v: &[f64]| {
            let mut a = <M::Lanes<L> as LaneMechanism<L>>::X::default();
            for (d, &s) in a.as_mut().iter_mut().zip(v) {
                *d = L::splat(s);
            }
            a
        };
        InputMotion::new(lanes(&self.x), lanes(&self.xd), lanes(&self.xdd))
    }

    /// Every lane's tick started afresh from its unknowns in `guess` (lane after lane), as the
    /// scalar walk restarts its tick; a lane that does not start leaves.
    fn start(&mut self, guess: &[f64], c: &Continuation) {
        let mut q = <M::Lanes<L> as LaneMechanism<L>>::Q::default();
        for (k, v) in q.as_mut().iter_mut().enumerate() {
            *v = L::from_fn(|lane| guess[lane * self.nu + k]);
        }
        let t = self.group.tick_start(&self.input(), &q, &c.options);
        for lane in 0..L::W {
            if t.lane_status(lane).0.is_err() {
                self.active &= !(1 << lane);
            }
        }
        self.tick = Some(t);
    }

    /// Every lane still in the lanes through the rows `rows` of `values` (indices, in the order
    /// walked), the tick started afresh every SEGMENT rows, each row handed to `emit`.
    fn walk(
        &mut self,
        rows: impl Iterator<Item = usize>,
        (values, index, h_max): (&[f64], usize, f64),
        c: &Continuation,
        guard: (&mechgen_runtime::guard::BranchGuard, L),
        emit: &mut dyn FnMut(usize, usize, RowRef<'_>),
    ) {
        for (d, r) in rows.enumerate() {
            if self.active == 0 {
                break;
            }
            if d > 0 && d % super::SEGMENT == 0 {
                self.renew(c);
            }
            self.tick_to(values[r], h_max, index, c, guard);
            self.emit_rows((r, values[r]), emit);
        }
    }

    /// The tick started afresh where every lane stands (the scalar walk's `renew`).
    fn renew(&mut self, c: &Continuation) {
        let Some(t) = &self.tick else { return };
        let mut guess = vec![0.0; L::W * self.nu];
        for lane in 0..L::W {
            let q = &mut guess[lane * self.nu..(lane + 1) * self.nu];
            t.lane_numbers(lane, q, &mut [], &mut [], &mut []);
        }
        self.start(&guess, c);
    }

    /// Every lane ticked to `target` in the scalar walk's substeps, each held to the branch rule;
    /// a lane whose substep fails, is refused or finds the budget spent leaves, as does one whose
    /// row's condition estimate asks the scalar walk to solve it afresh. One rule for every lane
    /// (the sets' guards differ in their length scales at most: `scales`).
    fn tick_to(
        &mut self,
        target: f64,
        h_max: f64,
        index: usize,
        c: &Continuation,
        (guard, scales): (&mechgen_runtime::guard::BranchGuard, L),
    ) {
        let Some(route) = Route::new(self.x[index], target, h_max) else {
            self.active = 0;
            return;
        };
        let nu = self.nu;
        for j in 1..=route.len() {
            for lane in 0..L::W {
                if self.active >> lane & 1 == 1 {
                    if self.allowance[lane] == 0 {
                        self.active &= !(1 << lane);
                    } else {
                        self.allowance[lane] -= 1;
                    }
                }
            }
            let Some(t) = &self.tick else { return };
            let (q, qd, qdd) = t.lanes_q();
            self.before[..nu].copy_from_slice(q);
            self.before[nu..2 * nu].copy_from_slice(qd);
            self.before[2 * nu..].copy_from_slice(qdd);
            let x_before = self.x[index];
            self.x[index] = route.end(j);
            let dt = (self.x[index] - x_before) / self.xd[index];
            let input = self.input();
            let Some(t) = &mut self.tick else { return };
            let kept = mechgen_runtime::simd::dispatch(GuardedTick {
                group: &self.group,
                t,
                input: &input,
                options: &c.options,
                rule: (guard, scales),
                before: &self.before,
                dt,
            });
            self.active &= kept;
        }
        let Some(t) = &self.tick else { return };
        for lane in 0..L::W {
            if self.active >> lane & 1 == 1 && t.lane_status(lane).1 >= RESOLVE_CONDITION {
                self.active &= !(1 << lane);
            }
        }
    }

    /// Row `r` (at input `target`) of every lane still in the lanes.
    fn emit_rows(
        &mut self,
        (r, target): (usize, f64),
        emit: &mut dyn FnMut(usize, usize, RowRef<'_>),
    ) {
        let Some(t) = &self.tick else { return };
        t.all_numbers(&mut self.q, &mut self.qd, &mut self.qdd, &mut self.points);
        let (nu, np) = (self.nu, self.np);
        for lane in 0..L::W {
            if self.active >> lane & 1 == 0 {
                continue;
            }
            let condition = t.lane_status(lane).1;
            let u = lane * nu..(lane + 1) * nu;
            emit(
                lane,
                r,
                Row {
                    input: target,
                    result: Ok(Solved {
                        q: &self.q[u.clone()],
                        qd: &self.qd[u.clone()],
                        qdd: &self.qdd[u],
                        points: &self.points[lane * np..(lane + 1) * np],
                        condition,
                    }),
                    stopped: None,
                },
            );
        }
    }
}
