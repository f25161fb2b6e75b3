// How moving bodies answer the fluid within one pressure solve (iterated two-way coupling). The
// solver reports the impulses its boundary term has applied so far this step; the bodies set
// their samples' velocities to what they would move at after taking them, so the solver's next
// iteration sees a body that yields (a box landing on a fluid film is slowed by it within the
// step, instead of pressing the film at its full speed until the pressure explodes). The
// impulses the bodies finally take are the solver's total, as without it (Eq. 35): the exchange
// stays equal and opposite. The trial motion carries the touching fluid's mass as well as the
// body's: every touching particle's increment is sized as if the body did not move, so a body
// answering with its own mass alone takes all their pushes at once and overshoots (a volume-map
// box under a squeezed film spun up to 530 rad/s within one step's iterations); with the added
// mass, the body's answer per iteration stays below what stops the squeeze. Weak coupling with
// sub-iterations in the sense of the paper's Section 3.5 ([ICS*14] weak, [GPB*19] strong); not
// [GPB*19]'s interlinked solver.
#pragma once
#include <span>
#include <vector>

#include "Simulation/NeighborSearch.h"
#include "Simulation/ParticleView.h"

namespace consph {

// A fluid-boundary pair whose sample belongs to a free dynamic body: fluid particle i and the
// pair's index e in the boundary neighbour lists.
struct MovingPair {
  Index fluid, pair;
};

class BodyResponse {
 public:
  virtual ~BodyResponse() = default;
  // The pairs of `lists` (this step's) whose sample belongs to a free dynamic body, in fluid
  // order; found once per step, so the iterations touch only these.
  virtual const std::vector<MovingPair>& movingPairs(const NeighborLists& lists, std::span<const Vector3r> fluidPositions,
                                                     std::span<const Real> fluidMasses, const BoundaryView& samples) = 0;
  // `impulses[p]`: the impulse the fluid has given the sample of movingPairs()[p] this step so
  // far. Sets the velocities of the free dynamic bodies' samples to
  // v + (J + m g dt) / (m + m_c), w + (I + I_c)^-1 L, where m_c and I_c are the mass and
  // inertia of the fluid particles touching the body (the bodies' own state is untouched).
  virtual void respond(std::span<const Vector3r> fluidPositions, const std::vector<Vector3r>& impulses, const Vector3r& gravity,
                       Real dt, const BoundaryView& samples) = 0;
  // The samples' velocities back to the bodies' own.
  virtual void restore(const BoundaryView& samples) = 0;
};

}  // namespace consph
