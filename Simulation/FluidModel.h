// One fluid: its material constants and its particles' fields (structure of arrays).
#pragma once
#include <string>
#include <vector>

#include "Simulation/ParticleFields.h"

namespace consph {

class FluidModel {
 public:
  FluidModel(std::string name, Real density0)
      : name_(std::move(name)),
        density0_(density0),
        positions(fields_.add<Vector3r>("position", FieldSorted | FieldExported, Vector3r::Zero())),
        velocities(fields_.add<Vector3r>("velocity", FieldSorted | FieldExported, Vector3r::Zero())),
        accelerations(fields_.add<Vector3r>("acceleration", FieldSorted, Vector3r::Zero())),
        densities(fields_.add<Real>("density", FieldSorted | FieldExported, density0)),
        pressures(fields_.add<Real>("solverPressure", FieldSorted | FieldExported, Real(0))),
        masses(fields_.add<Real>("mass", FieldSorted, Real(0))),
        ids(fields_.add<Index>("id", FieldSorted | FieldExported, Index(0))) {}
  FluidModel(const FluidModel&) = delete;
  FluidModel& operator=(const FluidModel&) = delete;

  const std::string& name() const { return name_; }
  Real density0() const { return density0_; }
  std::size_t size() const { return fields_.size(); }
  void resize(std::size_t n) { fields_.resize(n); }
  ParticleFields& fields() { return fields_; }

 private:
  std::string name_;
  Real density0_;
  ParticleFields fields_;

 public:
  // The fields every solver needs, as direct references (no name lookup in loops).
  std::vector<Vector3r>& positions;      // x_i (m)
  std::vector<Vector3r>& velocities;     // v_i (m/s)
  std::vector<Vector3r>& accelerations;  // non-pressure acceleration a_i^np (m/s^2)
  std::vector<Real>& densities;          // rho_i (kg/m^3), Eq. (14)
  // p_i (Pa) as the pressure solver found it: the multiplier that keeps particle i at rho0
  // (field "solverPressure"). The pressure field to read is the kernel average of it,
  // Simulation::updatePressureField (field "pressure").
  std::vector<Real>& pressures;
  std::vector<Real>& masses;             // m_i (kg)
  std::vector<Index>& ids;               // stable particle id across re-sorting
};

}  // namespace consph
