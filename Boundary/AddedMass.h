// The fluid a light body moves with. A body much lighter than the fluid it displaces blows up
// under the explicit coupling of Eq. (35): the impulse the fluid gives it in a step was solved
// against the body's old velocity, and with J / m its velocity changes far more than the fluid
// around it could follow (a 0.01 rho0 box: 440 m/s after two steps). This is the added-mass
// instability of partitioned fluid-structure coupling (Causin, Gerbeau & Nobile 2005; Banks,
// Henshaw & Schwendeman 2017 for rigid bodies in incompressible flow): the fluid that must be
// accelerated with the body is missing from its inertia. The remedy here keeps the exchange
// exact: the body takes the net impulse N = J + m g dt together with an added mass m_a of the
// fluid touching it, dv = N / (m + m_a) (and I + I_a for the angular impulse), and the touching
// fluid takes the rest of N as a rigid increment of its own velocities, so that body plus
// fluid gain exactly N and the angular impulse, as without it. A touching cloud that cannot
// take an angular impulse of its own (one or two particles, a line) moves with the body by the
// added share instead: momentum still exact, angular momentum not (AddedMass.cpp).
#pragma once
#include <vector>

#include "Boundary/RigidBody.h"

namespace consph {

// m_a = min(touching fluid's mass, max(0, c rho0 V - m)) with c = kAddedMassCoefficient: a
// body at least half as dense as the fluid is left as it is (Eq. 35 alone; the rest of the
// suite's bodies), a lighter one accelerates at most like a body of half the fluid's density.
// 1/2 is the added-mass coefficient of a sphere in potential flow (Lamb 1932, Sec. 92); a
// cube's is about 0.7, so the lightest bodies rise somewhat slower than they would.
inline constexpr Real kAddedMassCoefficient = Real(0.5);

// The smallest to largest principal moment of the touching fluid about its own centre below
// which it counts as degenerate (a point or a line of particles: 0 up to round-off; a flat
// layer under a box has 1/2) and moves with the body.
inline constexpr Real kMinInertiaRatio = Real(1e-4);

// The body's velocity increments from the net impulse N and the angular impulse L about its
// centre with the added mass `addedMass` of the fluid particles `touching`; the rest of the
// impulses goes to those particles' velocities. Without touching particles (or addedMass 0):
// the body's own update (RigidBody::applyImpulses).
struct BodyIncrement {
  Vector3r dv = Vector3r::Zero(), dw = Vector3r::Zero();
};
BodyIncrement shareWithTouchingFluid(const RigidBody& body, const Vector3r& N, const Vector3r& L, Real dt, Real addedMass,
                                     const std::vector<Index>& touching, const std::vector<Vector3r>& fluidPositions,
                                     const std::vector<Real>& fluidMasses, std::vector<Vector3r>& fluidVelocities);

}  // namespace consph
