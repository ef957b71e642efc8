//! Fleets (feature `sweep`): any number of instances of one generated mechanism, each with its
//! own params, inputs and state, ticked together: in groups of W SIMD lanes (`NAME::Lanes<L>`),
//! the groups across every core with the `parallel` feature ([`crate::batch::for_each_mut`]).
//! Instance `i` sits in lane `i % W` of group `i / W`; every instance's result or error is its
//! scalar tick's, to the last bit, whatever the threads.

use mechgen_runtime::{
    InputMotion, LaneMechanism, Lanes, SolveError, SolveOptions, StaticMechanism,
};

/// The lane type of `M` in `L`, and its state.
type Group<M, L> = <M as StaticMechanism<<L as Lanes>::Scalar>>::Lanes<L>;
type GroupTick<M, L> = <Group<M, L> as LaneMechanism<L>>::Tick;

/// Instances of `M` in lane groups of `L` (see the module).
pub struct Fleet<M: StaticMechanism<L::Scalar>, L: Lanes> {
    groups: Vec<(Group<M, L>, GroupTick<M, L>)>,
    len: usize,
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
        mechgen_runtime::error::len(inputs, len)?;
        mechgen_runtime::error::len(guesses, len)?;
        if len == 0 {
            return Err(SolveError::BadLength {
                expected: 1,
                got: 0,
            });
        }
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
    /// ticks), the lane groups across every core. A failed instance keeps its last state and its
    /// error; no instance changes another.
    pub fn tick(
        &mut self,
        inputs: &[InputMotion<M::X>],
        options: &SolveOptions<L::Scalar>,
    ) -> Result<(), SolveError> {
        mechgen_runtime::error::len(inputs, self.len)?;
        crate::batch::for_each_mut(&mut self.groups, |g, (lanes, t)| {
            lanes.tick(t, &group_input::<M, L>(inputs, g), options);
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
        Ok(<Group<M, L> as LaneMechanism<L>>::lane(t, i % L::W))
    }
}
