//! The scene-wide initial velocity ([`Scene::initial_velocity`]): a vehicle that starts
//! driving forward at v (docs/scenes.md §3.2 "a free forward speed starting at 5 m/s",
//! §3.6 "every body is given a forward velocity of 5 m/s").
//!
//! A uniform translation adds v to every body frame's origin velocity and nothing to its
//! angular velocity. With a given start it is added to each body's own velocity guess; with
//! a static start (whose equilibrium discards the guesses) each body's guess becomes the bare
//! translation, and the facade starts ALI3-P from the equilibrium with the formulation's
//! velocities of that guess. In natural coordinates (points move at v, unit vectors do not)
//! and in relative ones (the floating base's translation rate, in ground axes) a translation's
//! velocities do not depend on the configuration, so the guess taken at the scene's placement
//! holds at the equilibrium; ALI3-P's velocity projection (docs/methods.md §5.4 item 2) removes
//! what a constraint to the ground does not allow.

use std::borrow::Cow;

use crate::scene::{InitialState, Scene, V3, Velocity};

impl Scene {
    /// True when the scene gives every body a common start velocity.
    pub fn moves_at_start(&self) -> bool {
        self.initial_velocity.0 != [0.0; 3]
    }

    /// The scene with its [`Scene::initial_velocity`] handed to the bodies (module
    /// documentation); borrowed unchanged when it is zero.
    pub fn with_initial_velocity(&self) -> Cow<'_, Scene> {
        if !self.moves_at_start() {
            return Cow::Borrowed(self);
        }
        let v = self.initial_velocity.vec();
        let mut scene = self.clone();
        for body in &mut scene.bodies {
            body.velocity = match scene.solver.initial_state {
                InitialState::StaticEquilibrium => Velocity {
                    linear: V3(v.into()),
                    angular: V3::default(),
                },
                InitialState::Given => Velocity {
                    linear: V3((body.velocity.linear.vec() + v).into()),
                    angular: body.velocity.angular,
                },
            };
        }
        Cow::Owned(scene)
    }
}
