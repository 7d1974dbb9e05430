/* The unit of a quantity in a scene's system of units (units.h), for -help and the
   headers of probes.csv. */
#include <string.h>
#include "units.h"

const char *UnitName(const char system[], UnitDimension d)
{
  const int si = !strcmp(system, "SI");

  if (strcmp(system, "SI") && strcmp(system, "cgs")) return NULL;
  switch (d) {
  case UNIT_DENSITY:
    return si ? "kg/m^3" : "g/cm^3";
  case UNIT_VISCOSITY:
    return si ? "Pa s" : "g/(cm s)";
  case UNIT_PRESSURE:
    return si ? "Pa" : "dyn/cm^2";
  case UNIT_TIME:
    return "s";
  case UNIT_LENGTH:
    return si ? "m" : "cm";
  case UNIT_VELOCITY:
    return si ? "m/s" : "cm/s";
  case UNIT_ACCELERATION:
    return si ? "m/s^2" : "cm/s^2";
  case UNIT_FORCE_PER_DEPTH:
    return si ? "N/m" : "dyn/cm";
  case UNIT_FORCE:
    return si ? "N" : "dyn";
  case UNIT_JUMP:
    return si ? "m/s in the L2 norm over the interface" : "cm/s in the L2 norm over the interface";
  case UNIT_FLOW_RATE:
    return si ? "m^3/s" : "cm^3/s";
  case UNIT_FLOW_RATE_PER_DEPTH:
    return si ? "m^2/s" : "cm^2/s";
  case UNIT_RESISTANCE:
    return si ? "Pa s/m^3" : "dyn s/cm^5";
  case UNIT_RESISTANCE_PER_DEPTH:
    return si ? "Pa s/m^2" : "dyn s/cm^4";
  case UNIT_COMPLIANCE:
    return si ? "m^3/Pa" : "cm^5/dyn";
  case UNIT_COMPLIANCE_PER_DEPTH:
    return si ? "m^2/Pa" : "cm^4/dyn";
  case UNIT_STIFFNESS_PER_AREA:
    return si ? "Pa/m" : "dyn/cm^3";
  case UNIT_DAMPING_PER_AREA:
    return si ? "Pa s/m" : "dyn s/cm^3";
  case UNIT_AREA:
    return si ? "m^2" : "cm^2";
  case UNIT_VOLUME:
    return si ? "m^3" : "cm^3";
  case UNIT_ENERGY:
    return si ? "J" : "erg";
  case UNIT_ENERGY_PER_DEPTH:
    return si ? "J/m" : "erg/cm";
  }
  return NULL;
}
