#ifndef FSIOPT_UNITS_H
#define FSIOPT_UNITS_H

/* The unit of a quantity in a scene's system of units (Scene.units: "SI", "cgs",
   "nondimensional"), for -help and the headers of probes.csv; NULL when nondimensional. */
typedef enum {
  UNIT_DENSITY,
  UNIT_VISCOSITY,
  UNIT_PRESSURE,
  UNIT_TIME,
  UNIT_LENGTH,
  UNIT_VELOCITY,
  UNIT_ACCELERATION,
  UNIT_FORCE_PER_DEPTH, /* a force on a 2D body, per unit depth */
  UNIT_FORCE,
  UNIT_JUMP, /* the interface jump ||u - v_s||_{L2(Gamma_I)} */
  UNIT_FLOW_RATE,
  UNIT_FLOW_RATE_PER_DEPTH, /* through a 2D face set, per unit depth */
  UNIT_RESISTANCE,          /* of a 0D outlet: pressure per flow rate */
  UNIT_RESISTANCE_PER_DEPTH,
  UNIT_COMPLIANCE, /* of a 0D outlet: volume per pressure */
  UNIT_COMPLIANCE_PER_DEPTH,
  UNIT_STIFFNESS_PER_AREA, /* of a Robin support: pressure per length */
  UNIT_DAMPING_PER_AREA,   /* pressure per velocity */
  UNIT_AREA,
  UNIT_VOLUME,
  UNIT_ENERGY,
  UNIT_ENERGY_PER_DEPTH /* of a 2D region, per unit depth */
} UnitDimension;

const char *UnitName(const char system[], UnitDimension);
#endif
