//! Fleets (feature `sweep`): any number of instances of one generated mechanism, each with its
//! own params, inputs and state, ticked together: in groups of W SIMD lanes (`NAME::Lanes<L>`),
//! the groups across every core with the `parallel` feature ([`crate::batch::for_each_mut`]).
//! Instance `i` sits in lane `i % W` of group `i / W`; every instance's result or error is its
//! scalar tick's, to the last bit, whatever the threads. [`DynFleet`] is the same API for
//! run-time engines (the generic engine of `--file`): one instance at a time, across every core.

use mechgen_runtime::tick::{step_to, taylor};
use mechgen_runtime::{
    DynMechanism, DynState, InputMotion, LaneMechanism, Lanes, Real, SolveError, SolveOptions,
    StaticMechanism,
};

/// The lane type of `M` in `L`, and its state.
type Group<M, L> = <M as StaticMechanism<<L as Lanes>::Scalar>>::Lanes<L>;
type GroupTick<M, L> = <Group<M, L> as LaneMechanism<L>>::Tick;

/// Instances of `M` in lane groups of `L` (see the module).
pub struct Fleet<M: StaticMechanism<L::Scalar>, L: Lanes> {
    groups: Vec<(Group<M, L>, GroupTick<M, L>)>,
    len: usize,
}

/// `BadLength` unless there is at least one instance and an input and a guess for each of the
/// `len`.
fn one_each<A, B>(len: usize, inputs: &[A], guesses: &[B]) -> Result<(), SolveError> {
    mechgen_runtime::error::len(inputs, len)?;
    mechgen_runtime::error::len(guesses, len)?;
    if len == 0 {
        return Err(SolveError::BadLength {
            expected: 1,
            got: 0,
        });
    }
    Ok(())
}

/// Lane `i` of a group is instance `g·W + i`, the last instance standing in for the missing ones
/// of the last group.
fn member<U>(items: &[U], g: usize, i: usize, w: usize) -> &U {
    &items[(g * w + i).min(items.len() - 1)]
}

/// The inputs of group `g` in lanes.
fn group_input<M: StaticMechanism<L::Scalar>, L: Lanes>(
    inputs: &[InputMotion<M::X>],
    g: usize,
) -> InputMotion<<Group<M, L> as LaneMechanism<L>>::X> {
    let w = L::W;
    let lanes = |f: &dyn Fn(&InputMotion<M::X>) -> &M::X| {
        let mut x = <Group<M, L> as LaneMechanism<L>>::X::default();
        for (k, v) in x.as_mut().iter_mut().enumerate() {
            *v = L::from_fn(|i| f(member(inputs, g, i, w)).as_ref()[k]);
        }
        x
    };
    InputMotion::new(lanes(&|m| &m.x), lanes(&|m| &m.xd), lanes(&|m| &m.xdd))
}

impl<M: StaticMechanism<L::Scalar>, L: Lanes> Fleet<M, L> {
    /// The first tick of every instance: `mechanisms[i]` from `guesses[i]` at `inputs[i]` (three
    /// slices of one length, at least one instance: else `BadLength`). An instance that does not
    /// start has its error in [`Fleet::state`] and starts again at the next tick.
    pub fn start(
        mechanisms: &[M],
        inputs: &[InputMotion<M::X>],
        guesses: &[M::Q],
        options: &SolveOptions<L::Scalar>,
    ) -> Result<Self, SolveError> {
        let len = mechanisms.len();
        one_each(len, inputs, guesses)?;
        let w = L::W;
        let mut groups: Vec<_> = (0..len.div_ceil(w))
            .map(|g| {
                let lanes = Group::<M, L>::from_fn(|i| member(mechanisms, g, i, w).clone());
                let mut guess = <Group<M, L> as LaneMechanism<L>>::Q::default();
                for (k, v) in guess.as_mut().iter_mut().enumerate() {
                    *v = L::from_fn(|i| member(guesses, g, i, w).as_ref()[k]);
                }
                let t = lanes.tick_start(&group_input::<M, L>(inputs, g), &guess, options);
                (lanes, t)
            })
            .collect();
        groups.shrink_to_fit();
        Ok(Fleet { groups, len })
    }

    /// How many instances.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the fleet is empty (never: [`Fleet::start`] needs one instance).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// One tick of every instance to `inputs[i]` (one per instance, else `BadLength` and nothing
    /// ticks), the lane groups across every core, each with the CPU's widest vector
    /// instructions (`tick_widest`). A failed instance keeps its last state and its error; no
    /// instance changes another.
    pub fn tick(
        &mut self,
        inputs: &[InputMotion<M::X>],
        options: &SolveOptions<L::Scalar>,
    ) -> Result<(), SolveError> {
        mechgen_runtime::error::len(inputs, self.len)?;
        crate::batch::for_each_mut(&mut self.groups, |g, (lanes, t)| {
            lanes.tick_widest(t, &group_input::<M, L>(inputs, g), options);
        });
        Ok(())
    }

    /// Instance `i` (`i < len`, else `BadLength`): the status of its last tick and its state as
    /// the scalar tick (`M::Tick`, which reads as the solved state).
    pub fn state(&self, i: usize) -> Result<(Result<(), SolveError>, M::Tick), SolveError> {
        if i >= self.len {
            return Err(SolveError::BadLength {
                expected: self.len,
                got: i,
            });
        }
        let (_, t) = &self.groups[i / L::W];
        <Group<M, L> as LaneMechanism<L>>::lane(t, i % L::W).ok_or(SolveError::BadLength {
            expected: self.len,
            got: i,
        })
    }
}

/// Instances of a run-time engine ([`DynMechanism`]: the generic engine of `--file`, or any
/// other), the same API as [`Fleet`], ticked one by one (no lanes) across every core: each tick
/// is a whole solve (`solve_in_place`) from the second-order prediction of the instance's last
/// state, as the generic engine's `step` bench ticks. A failed instance keeps its last state and
/// its error (and, if it never started, tries again from its guess at the next tick).
pub struct DynFleet<T: Real, M> {
    members: Vec<DynMember<T, M>>,
}

/// One instance of a [`DynFleet`]: the engine, its state, the status of its last tick and
/// whether it has started; the unknowns a closed form solves (the predictor keeps them) and the
/// state being solved.
struct DynMember<T: Real, M> {
    engine: M,
    state: DynState<T>,
    status: Result<(), SolveError>,
    started: bool,
    keep: Vec<bool>,
    next: DynState<T>,
}

impl<T: Real, M: DynMechanism<T> + Send + Sync> DynFleet<T, M> {
    /// The first solve of every instance: `engines[i]` from `guesses[i]` at `inputs[i]` (one
    /// length, at least one instance, each vector of its engine's size: else `BadLength`).
    pub fn start(
        engines: Vec<M>,
        inputs: &[InputMotion<Vec<T>>],
        guesses: &[Vec<T>],
        options: &SolveOptions<T>,
    ) -> Result<Self, SolveError> {
        let len = engines.len();
        one_each(len, inputs, guesses)?;
        let mut members = Vec::with_capacity(len);
        for ((engine, input), guess) in engines.into_iter().zip(inputs).zip(guesses) {
            let info = engine.info();
            mechgen_runtime::error::len(&input.x, info.inputs.len())?;
            mechgen_runtime::error::len(guess, info.unknowns.len())?;
            let state = DynState::new(
                InputMotion::new(&input.x[..], &input.xd[..], &input.xdd[..]),
                guess,
                info.points.len(),
            );
            let mut keep = vec![false; info.unknowns.len()];
            for (block, _) in info.blocks.iter().zip(&info.closed).filter(|(_, c)| **c) {
                for &k in block {
                    keep[k] = true;
                }
            }
            members.push(DynMember {
                engine,
                next: state.clone(),
                state,
                status: Ok(()),
                started: false,
                keep,
            });
        }
        let mut fleet = DynFleet { members };
        fleet.tick(inputs, options)?;
        Ok(fleet)
    }

    /// How many instances.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// Whether the fleet is empty (never: [`DynFleet::start`] needs one instance).
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// One tick of every instance to `inputs[i]` (one per instance, each of its engine's input
    /// count, else `BadLength` and nothing ticks), across every core.
    pub fn tick(
        &mut self,
        inputs: &[InputMotion<Vec<T>>],
        options: &SolveOptions<T>,
    ) -> Result<(), SolveError> {
        mechgen_runtime::error::len(inputs, self.members.len())?;
        for (m, input) in self.members.iter().zip(inputs) {
            mechgen_runtime::error::len(&input.x, m.state.x.len())?;
            mechgen_runtime::error::len(&input.xd, m.state.x.len())?;
            mechgen_runtime::error::len(&input.xdd, m.state.x.len())?;
        }
        crate::batch::for_each_mut(&mut self.members, |i, m| {
            let input = &inputs[i];
            let (s, next) = (&m.state, &mut m.next);
            next.clone_from(s);
            if m.started {
                // The runtime's predictor, closed-form unknowns kept, as every tick predicts.
                let dt = step_to(&s.x, &input.x, &s.xd);
                let keep: &[bool] = if options.closed_forms { &m.keep } else { &[] };
                taylor(&s.q, &s.qd, &s.qdd, dt, keep, &mut next.q);
            }
            next.x.clone_from(&input.x);
            next.xd.clone_from(&input.xd);
            next.xdd.clone_from(&input.xdd);
            m.status = m.engine.solve_in_place(next, options);
            if m.status.is_ok() {
                std::mem::swap(&mut m.state, &mut m.next);
                m.started = true;
            }
        });
        Ok(())
    }

    /// Instance `i` (`i < len`, else `BadLength`): the status of its last tick and its state
    /// (its last solved state; its guess if it never started).
    pub fn state(&self, i: usize) -> Result<(Result<(), SolveError>, &DynState<T>), SolveError> {
        match self.members.get(i) {
            Some(m) => Ok((m.status, &m.state)),
            None => Err(SolveError::BadLength {
                expected: self.members.len(),
                got: i,
            }),
        }
    }
}
