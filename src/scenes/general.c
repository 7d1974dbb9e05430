/* Scene general: a case from an options file and a mesh, no C. Each face set of the fluid's
   and the structure's mesh, by its name (a gmsh physical name; bottom, right, top, left on a
   2D box; or its number), gets one condition:

     -fluid_boundary_NAME      wall | velocity | flow | traction | pressure | open | resistance | rcr | interface
     -structure_boundary_NAME  clamped | free | traction | pressure | robin | interface

   with its datum as an expression in x, y, z, t (expression.h) where the condition takes one:
   -fluid_boundary_NAME_velocity, -..._traction (vectors, components separated by commas) and
   -..._pressure (a scalar p: the traction -p n). A flow inlet takes -..._flow_rate Q(t) (in),
   -..._profile plug | parabolic | womersley, and Womersley's -..._period and -..._harmonics
   (flow_profile.h). A 0D outlet (fluid_outlets.c) takes
   -..._resistance R or -..._rcr R_p,C,R_d, and -..._distal_pressure P_d (default 0). A Robin
   support of the wall (structure_robin.c) takes -..._stiffness k and -..._damping c. The fluid's mesh follows the interface and
   stays put on every other face set. -probes_interface_displacement gives probes.csv's
   interface points; -units the system the values are in. The meshes, materials and solver
   settings are the options every scene has. */
#include "scene.h"
#include "fluid.h"
#include "structure.h"
#include "options.h"
#include "fem.h"
#include "mesh.h"
#include "expression.h"
#include "general_symbols.h"
#include "flow_profile.h"

#pragma GCC diagnostic ignored "-Wunused-parameter"

#define MAX_FACE_SETS 32

typedef enum {
  FLUID_SIDE,
  STRUCTURE_SIDE
} Side;

static const char *const fluid_conditions[]     = {"wall", "velocity", "flow", "traction", "pressure", "open", "resistance", "rcr", "interface", NULL};
static const char *const profiles[]             = {"plug", "parabolic", "womersley", NULL};
static const char *const structure_conditions[] = {"clamped", "free", "traction", "pressure", "robin", "interface", NULL};

/* PETSc fixes the pointwise kernels' signature (no context): the traction data of each side's
   traction slots live here, one kernel per slot reads its own */
static Expression traction_data[2][FSIOPT_MAX_BOUNDARIES];
static PetscBool  traction_is_pressure[2][FSIOPT_MAX_BOUNDARIES];
static Expression velocity_data[FSIOPT_MAX_BOUNDARIES]; /* the fluid's inlets: PETSc hands them to ExpressionField */
static FlowProfile flow_data[FSIOPT_MAX_BOUNDARIES];     /* and its flow-rate inlets */
static Expression  body_force[2];                        /* -fluid_body_force, -structure_body_force */
static PetscBool   body_acceleration[2];                 /* given per unit mass (-*_body_acceleration) */

/* the waveforms and parameters the expressions may use (general_symbols.c) */
static const ExpressionSymbols *symbols;

/* adds -load h(x, t), h the traction given, or -p n for a pressure */
static inline void AddTraction(Side side, PetscInt slot, PetscInt dim, const PetscReal x[], const PetscReal n[],
                               const PetscScalar constants[], PetscScalar f0[])
{
  const PetscReal   time = PetscRealPart(constants[side == FLUID_SIDE ? FLUID_TIME : STRUCTURE_TIME]);
  const PetscScalar load = constants[side == FLUID_SIDE ? FLUID_LOAD : STRUCTURE_LOAD];
  PetscScalar       h[3];

  ExpressionEvaluate(traction_data[side][slot], time, dim, x, h);
  if (traction_is_pressure[side][slot])
    for (PetscInt d = 0; d < dim; ++d) f0[d] += load * h[0] * n[d]; /* -load (-p n), in the built-in scenes' order */
  else
    for (PetscInt d = 0; d < dim; ++d) f0[d] -= load * h[d];
}

#define TRACTION_KERNEL(NAME, SIDE, SLOT) \
  static void NAME(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], \
                   const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], \
                   const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], \
                   PetscReal t, const PetscReal x[], const PetscReal n[], PetscInt numConstants, \
                   const PetscScalar constants[], PetscScalar f0[]) \
  { \
    AddTraction(SIDE, SLOT, dim, x, n, constants, f0); \
  }
TRACTION_KERNEL(FluidTraction0, FLUID_SIDE, 0)
TRACTION_KERNEL(FluidTraction1, FLUID_SIDE, 1)
TRACTION_KERNEL(FluidTraction2, FLUID_SIDE, 2)
TRACTION_KERNEL(FluidTraction3, FLUID_SIDE, 3)
TRACTION_KERNEL(FluidTraction4, FLUID_SIDE, 4)
TRACTION_KERNEL(FluidTraction5, FLUID_SIDE, 5)
TRACTION_KERNEL(FluidTraction6, FLUID_SIDE, 6)
TRACTION_KERNEL(FluidTraction7, FLUID_SIDE, 7)
TRACTION_KERNEL(StructureTraction0, STRUCTURE_SIDE, 0)
TRACTION_KERNEL(StructureTraction1, STRUCTURE_SIDE, 1)
TRACTION_KERNEL(StructureTraction2, STRUCTURE_SIDE, 2)
TRACTION_KERNEL(StructureTraction3, STRUCTURE_SIDE, 3)
TRACTION_KERNEL(StructureTraction4, STRUCTURE_SIDE, 4)
TRACTION_KERNEL(StructureTraction5, STRUCTURE_SIDE, 5)
TRACTION_KERNEL(StructureTraction6, STRUCTURE_SIDE, 6)
TRACTION_KERNEL(StructureTraction7, STRUCTURE_SIDE, 7)

static const BdResidualKernel traction_kernels[2][FSIOPT_MAX_BOUNDARIES] = {
  {FluidTraction0,     FluidTraction1,     FluidTraction2,     FluidTraction3,     FluidTraction4,     FluidTraction5,
   FluidTraction6,     FluidTraction7    },
  {StructureTraction0, StructureTraction1, StructureTraction2, StructureTraction3, StructureTraction4, StructureTraction5,
   StructureTraction6, StructureTraction7},
};

/* -load f(x, t), f the body force per unit volume, or rho a(x, t) given the acceleration a */
static inline void AddBodyForce(Side side, PetscInt dim, const PetscReal x[], const PetscScalar constants[],
                                PetscScalar f0[])
{
  const PetscReal   time = PetscRealPart(constants[side == FLUID_SIDE ? FLUID_TIME : STRUCTURE_TIME]);
  PetscScalar       load = constants[side == FLUID_SIDE ? FLUID_LOAD : STRUCTURE_LOAD];
  PetscScalar       f[3];

  if (body_acceleration[side]) load *= constants[side == FLUID_SIDE ? FLUID_RHO : STRUCTURE_RHO];
  ExpressionEvaluate(body_force[side], time, dim, x, f);
  for (PetscInt d = 0; d < dim; ++d) f0[d] -= load * f[d];
}

#define BODY_FORCE_KERNEL(NAME, SIDE) \
  static void NAME(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], \
                   const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], \
                   const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], \
                   PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], \
                   PetscScalar f0[]) \
  { \
    AddBodyForce(SIDE, dim, x, constants, f0); \
  }
BODY_FORCE_KERNEL(FluidBodyForceKernel, FLUID_SIDE)
BODY_FORCE_KERNEL(StructureBodyForceKernel, STRUCTURE_SIDE)

/* -fluid_body_force, -structure_body_force: a vector expression in x, y, z, t */
static PetscErrorCode ReadBodyForce(Side side, PetscInt dim, PhysicsData *data)
{
  const char *option = side == FLUID_SIDE ? "-fluid_body_force" : "-structure_body_force";
  const char *per_mass = side == FLUID_SIDE ? "-fluid_body_acceleration" : "-structure_body_acceleration";
  char        text[1024], accel[1024];
  PetscBool   given, given_accel;

  PetscFunctionBeginUser;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene general: body forces", "scene");
  PetscCall(PetscOptionsString(option, "a force per unit volume over the domain, a vector expression in x, y, z, t",
                               NULL, "", text, sizeof(text), &given));
  PetscCall(PetscOptionsString(per_mass,
                               "a force per unit mass (an acceleration: gravity is 0, -g), a vector expression in x, y, "
                               "z, t; the side's density multiplies it",
                               NULL, "", accel, sizeof(accel), &given_accel));
  PetscOptionsEnd();
  PetscCheck(!given || !given_accel, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "options %s and %s: give one of them", option,
             per_mass);
  if (!given && !given_accel) PetscFunctionReturn(0);
  PetscCall(ExpressionCreate(PETSC_COMM_WORLD, given ? option : per_mass, given ? text : accel, dim, symbols,
                             &body_force[side]));
  body_acceleration[side] = given_accel;
  data->load_value_kernel = side == FLUID_SIDE ? FluidBodyForceKernel : StructureBodyForceKernel;
  PetscFunctionReturn(0);
}

/* -fluid_body_faces: the face sets of a body whose force (drag, lift: fluid_forces.c's
   volume-weighted form) probes.csv records and summary.json's quantities summarize */
static PetscErrorCode ReadBodyFaces(PetscInt dim, PhysicsData *data)
{
  MeshPhysicalName sets[MAX_FACE_SETS];
  char            *texts[FSIOPT_MAX_BOUNDARIES];
  PetscInt         nsets, n = FSIOPT_MAX_BOUNDARIES;
  PetscBool        given;

  PetscFunctionBeginUser;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene general: the force on a body", "scene");
  PetscCall(PetscOptionsStringArray("-fluid_body_faces",
                                    "face sets (names or numbers) of a body whose force from the fluid (drag, lift) "
                                    "probes.csv records",
                                    NULL, texts, &n, &given));
  PetscOptionsEnd();
  if (!given) PetscFunctionReturn(0);
  PetscCall(MeshFaceSetNames(PETSC_COMM_WORLD, "fluid_", dim, MAX_FACE_SETS, &nsets, sets));
  for (PetscInt i = 0; i < n; ++i) {
    PetscInt value;
    PetscCall(MeshFaceSetFind(nsets, sets, texts[i], &value));
    PetscCheck(value > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "option -fluid_body_faces: the fluid mesh has no face set %s",
               texts[i]);
    data->force_faces[data->n_force_faces++] = value;
    PetscCall(PetscFree(texts[i]));
  }
  PetscFunctionReturn(0);
}

/* a velocity given by an expression, as PETSc's boundary values take it */
static PetscErrorCode ExpressionField(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *u,
                                      void *ctx)
{
  ExpressionEvaluate((Expression)ctx, t, dim, x, u);
  return 0;
}

static PetscErrorCode DestroyExpressions(void *ctx)
{
  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < FSIOPT_MAX_BOUNDARIES; ++b) {
    PetscCall(ExpressionDestroy(&traction_data[FLUID_SIDE][b]));
    PetscCall(ExpressionDestroy(&traction_data[STRUCTURE_SIDE][b]));
    PetscCall(ExpressionDestroy(&velocity_data[b]));
    PetscCall(FlowProfileDestroy(&flow_data[b]));
  }
  PetscCall(ExpressionDestroy(&body_force[FLUID_SIDE]));
  PetscCall(ExpressionDestroy(&body_force[STRUCTURE_SIDE]));
  body_acceleration[FLUID_SIDE] = body_acceleration[STRUCTURE_SIDE] = PETSC_FALSE;
  PetscCall(GeneralSymbolsDestroy());
  symbols = NULL;
  PetscFunctionReturn(0);
}

/* The face sets of a side's mesh by name (mesh.h); each also answers to its number. */
static PetscErrorCode FaceSets(const char prefix[], PetscInt dim, PetscInt *n, MeshPhysicalName sets[])
{
  PetscFunctionBeginUser;
  PetscCall(MeshFaceSetNames(PETSC_COMM_WORLD, prefix, dim, MAX_FACE_SETS, n, sets));
  PetscCheck(*n > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
             "scene general: the %s mesh has no named face sets (-%sdm_plex_filename: a gmsh file with physical names, "
             "or a 2D box)",
             prefix[0] == 'f' ? "fluid" : "structure", prefix);
  PetscFunctionReturn(0);
}

/* An option of the side's family that no face set read names a face set the mesh lacks:
   stop, naming it and the face sets there are. */
static PetscErrorCode CheckNoOtherFaceSets(const char prefix[], PetscInt nsets, const MeshPhysicalName sets[])
{
  char      family[64], names[512] = "";
  PetscInt  n;
  char   **left, **values;
  PetscBool allowed = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-options_allow_unused", &allowed, NULL));
  if (allowed) PetscFunctionReturn(0); /* the check of unused options warns of them */
  PetscCall(PetscSNPrintf(family, sizeof(family), "%sboundary_", prefix)); /* PETSc's names come without the dash */
  for (PetscInt i = 0; i < nsets; ++i) {
    PetscCall(PetscStrlcat(names, i ? ", " : "", sizeof(names)));
    PetscCall(PetscStrlcat(names, sets[i].name, sizeof(names)));
  }
  PetscCall(PetscOptionsLeftGet(NULL, &n, &left, &values));
  for (PetscInt i = 0; i < n; ++i) {
    PetscBool ours;
    PetscCall(PetscStrncmp(left[i], family, strlen(family), &ours));
    if (!ours) continue;
    {
      char        message[1024];
      const char *set = NULL; /* the face set whose datum it would be */
      for (PetscInt k = 0; k < nsets && !set; ++k) {
        const size_t length = strlen(family) + strlen(sets[k].name);
        if (!strncmp(left[i] + strlen(family), sets[k].name, strlen(sets[k].name)) && left[i][length] == '_')
          set = sets[k].name;
      }
      if (set)
        PetscCall(PetscSNPrintf(message, sizeof(message),
                                "option -%s: the condition of the face set %s (-%s%s) takes no such datum", left[i],
                                set, family, set));
      else
        PetscCall(PetscSNPrintf(message, sizeof(message),
                                "option -%s: the %s mesh has no face set of that name; its face sets: %s", left[i],
                                prefix[0] == 'f' ? "fluid" : "structure", names));
      PetscCall(PetscOptionsLeftRestore(NULL, &n, &left, &values));
      SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "%s", message);
    }
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &left, &values));
  PetscFunctionReturn(0);
}

/* A 0D outlet on the face set: its model's parameters (-NAME_resistance R, or -NAME_rcr
   R_p,C,R_d; -NAME_distal_pressure P_d), and the traction kernel of its slot */
static PetscErrorCode ReadOutlet(PetscOptionItems *PetscOptionsObject, const char option[], const char condition[],
                                 MeshPhysicalName set, PhysicsData *data, BdResidualKernel *kernel)
{
  const PetscBool rcr = !strcmp(condition, "rcr") ? PETSC_TRUE : PETSC_FALSE;
  char            datum_option[160], pd_option[160];
  PetscReal       values[3] = {0, 0, 0};
  PetscInt        n         = rcr ? 3 : 1;
  PetscBool       given;
  OutletModel    *m;

  PetscFunctionBeginUser;
  PetscCheck(data->n_outlets < FSIOPT_MAX_OUTLETS, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option %s: at most %d 0D outlets", option, FSIOPT_MAX_OUTLETS);
  m = &data->outlets[data->n_outlets];
  PetscCall(PetscSNPrintf(datum_option, sizeof(datum_option), "%s_%s", option, condition));
  PetscCall(PetscSNPrintf(pd_option, sizeof(pd_option), "%s_distal_pressure", option));
  PetscCall(PetscOptionsRealArray(datum_option,
                                  rcr ? "the three-element Windkessel's R_p,C,R_d (pressure per flow rate, flow "
                                        "rate times time per pressure, pressure per flow rate)"
                                      : "the resistance R of p = R Q + P_d (pressure per flow rate)",
                                  NULL, values, &n, &given));
  PetscCheck(given && n == (rcr ? 3 : 1), PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
             "option %s %s: expected %s %s", option, condition, datum_option,
             rcr ? "R_p,C,R_d (three numbers)" : "R (one number)");
  for (PetscInt i = 0; i < n; ++i)
    PetscCheck(values[i] >= 0 && (PetscIsNormalReal(values[i]) || values[i] == 0), PETSC_COMM_WORLD,
               PETSC_ERR_ARG_OUTOFRANGE, "option %s: expected finite numbers >= 0, got %g", datum_option,
               (double)values[i]);
  PetscCheck(!rcr || (values[1] > 0 && values[2] > 0), PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option %s: C and R_d must be > 0 (for a resistance alone: %s resistance)", datum_option, option);
  m->distal_pressure = 0;
  PetscCall(PetscOptionsReal(pd_option, "the 0D outlet's distal pressure P_d", NULL, m->distal_pressure,
                             &m->distal_pressure, NULL));
  PetscCheck(PetscIsNormalReal(m->distal_pressure) || m->distal_pressure == 0, PETSC_COMM_WORLD,
             PETSC_ERR_ARG_OUTOFRANGE, "option %s: expected a finite pressure", pd_option);
  m->proximal_resistance = values[0];
  m->capacitance         = rcr ? values[1] : 0;
  m->distal_resistance   = rcr ? values[2] : 0;
  m->face                = set.value;
  PetscCall(PetscStrncpy(m->name, set.name, sizeof(m->name)));
  *kernel = FluidOutletKernel(data->n_outlets++);
  PetscFunctionReturn(0);
}

/* A Robin support of the wall: the traction -(k eta + c etadot), -NAME_stiffness k > 0 and
   -NAME_damping c >= 0 per unit area */
static PetscErrorCode ReadRobin(PetscOptionItems *PetscOptionsObject, const char option[], PetscInt face,
                                PhysicsData *data)
{
  char      k_option[160], c_option[160];
  PetscReal k = 0, c = 0;
  PetscBool given;

  PetscFunctionBeginUser;
  PetscCheck(data->n_robin < FSIOPT_MAX_BOUNDARIES, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option %s: at most %d Robin supports", option, FSIOPT_MAX_BOUNDARIES);
  PetscCall(PetscSNPrintf(k_option, sizeof(k_option), "%s_stiffness", option));
  PetscCall(PetscSNPrintf(c_option, sizeof(c_option), "%s_damping", option));
  PetscCall(OptionsDeclareUnit(k_option, UNIT_STIFFNESS_PER_AREA));
  PetscCall(OptionsDeclareUnit(c_option, UNIT_DAMPING_PER_AREA));
  PetscCall(PetscOptionsReal(k_option, "robin: the support's stiffness k per unit area (the traction -k eta)", NULL, k,
                             &k, &given));
  PetscCheck(given, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "option %s robin: expected %s, the stiffness k > 0 per unit area",
             option, k_option);
  PetscCheck(k > 0 && PetscIsNormalReal(k), PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option %s: expected a finite stiffness > 0, got %g", k_option, (double)k);
  PetscCall(PetscOptionsReal(c_option, "robin: the support's damping c per unit area (the traction -c d(eta)/dt)", NULL,
                             c, &c, NULL));
  PetscCheck(c >= 0 && (c == 0 || PetscIsNormalReal(c)), PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option %s: expected a finite damping >= 0, got %g", c_option, (double)c);
  data->robin_faces[data->n_robin]     = face;
  data->robin_stiffness[data->n_robin] = k;
  data->robin_damping[data->n_robin++] = c;
  PetscFunctionReturn(0);
}

/* A flow-rate inlet: -NAME_flow_rate Q(t) (flowing in), -NAME_profile, Womersley's -NAME_period
   and -NAME_harmonics */
static PetscErrorCode ReadFlowInlet(PetscOptionItems *PetscOptionsObject, const char option[], FlowProfile *profile)
{
  char       rate_option[160], profile_option[160], period_option[160], harmonics_option[160], text[1024];
  PetscInt   kind = FLOW_PROFILE_PARABOLIC, harmonics = 16;
  PetscReal  period = 0;
  PetscBool  given;
  Expression rate;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(rate_option, sizeof(rate_option), "%s_flow_rate", option));
  PetscCall(PetscSNPrintf(profile_option, sizeof(profile_option), "%s_profile", option));
  PetscCall(PetscSNPrintf(period_option, sizeof(period_option), "%s_period", option));
  PetscCall(PetscSNPrintf(harmonics_option, sizeof(harmonics_option), "%s_harmonics", option));
  PetscCall(PetscOptionsString(rate_option, "the flow rate in through the face set, an expression in t", NULL, "", text,
                               sizeof(text), &given));
  PetscCheck(given, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "option %s flow: expected %s, the flow rate in as an "
             "expression in t", option, rate_option);
  PetscCall(PetscOptionsEList(profile_option, "the velocity profile across the face set", NULL, profiles, 3,
                              profiles[kind], &kind, NULL));
  PetscCall(PetscOptionsReal(period_option, "womersley: the period of the flow rate (its Fourier series)", NULL,
                             period, &period, &given));
  PetscCall(OptionsIntInRange(PetscOptionsObject, harmonics_option,
                              "womersley: the flow rate's harmonics the profile follows", 1, 64, &harmonics));
  PetscCheck(kind != FLOW_PROFILE_WOMERSLEY || (given && period > 0 && PetscIsNormalReal(period)), PETSC_COMM_WORLD,
             PETSC_ERR_ARG_WRONG, "option %s: a womersley profile needs %s, the flow rate's period (> 0)",
             profile_option, period_option);
  PetscCall(ExpressionCreate(PETSC_COMM_WORLD, rate_option, text, 1, symbols, &rate));
  PetscCall(FlowProfileCreate(option, (FlowProfileKind)kind, rate, period, harmonics, profile));
  PetscFunctionReturn(0);
}

/* One side's conditions, face set by face set, into its PhysicsData. */
static PetscErrorCode ReadConditions(Side side, PetscInt dim, PetscBool coupled, PhysicsData *data)
{
  const char *const *conditions = side == FLUID_SIDE ? fluid_conditions : structure_conditions;
  const char        *prefix     = side == FLUID_SIDE ? "fluid_" : "structure_";
  MeshPhysicalName   sets[MAX_FACE_SETS];
  PetscInt           nsets, nconditions = 0;
  char               list[128] = "";

  PetscFunctionBeginUser;
  while (conditions[nconditions]) {
    PetscCall(PetscStrlcat(list, nconditions ? ", " : "", sizeof(list)));
    PetscCall(PetscStrlcat(list, conditions[nconditions++], sizeof(list)));
  }
  PetscCall(FaceSets(prefix, dim, &nsets, sets));
  PetscCall(OptionsDeclareFamily(side == FLUID_SIDE ? "-fluid_boundary_" : "-structure_boundary_"));
  /* a title of each side's own: PETSc lists a title's options once */
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL,
                    side == FLUID_SIDE ? "Scene general: the fluid's face sets" : "Scene general: the structure's face sets",
                    "scene");
  for (PetscInt i = 0; i < nsets; ++i) {
    char        option[128], datum_option[160], text[1024], help[256];
    const char *condition;
    PetscInt    which = -1;
    PetscBool   given;

    PetscCall(PetscSNPrintf(option, sizeof(option), "-%sboundary_%s", prefix, sets[i].name));
    PetscCall(PetscSNPrintf(help, sizeof(help), "the condition on the %s face set %s (%" PetscInt_FMT ")",
                            side == FLUID_SIDE ? "fluid's" : "structure's", sets[i].name, sets[i].value));
    PetscCall(PetscOptionsEList(option, help, NULL, conditions, nconditions, "none", &which, &given));
    {
      char      by_number[128];
      PetscBool numbered;
      PetscCall(PetscSNPrintf(by_number, sizeof(by_number), "-%sboundary_%" PetscInt_FMT, prefix, sets[i].value));
      PetscCall(PetscOptionsHasName(NULL, NULL, by_number, &numbered));
      PetscCheck(!given || !numbered || !strcmp(option, by_number), PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
                 "options %s and %s: two conditions for one face set (%s is %" PetscInt_FMT "); give one", option,
                 by_number, sets[i].name, sets[i].value);
      if (!given) { /* by its number */
        PetscCall(PetscStrncpy(option, by_number, sizeof(option)));
        PetscCall(PetscOptionsGetEList(NULL, NULL, option, conditions, nconditions, &which, &given));
      }
    }
    PetscCheck(given, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
               "scene general: the %s face set %s (%" PetscInt_FMT ") has no condition: expected -%sboundary_%s one of %s",
               side == FLUID_SIDE ? "fluid" : "structure", sets[i].name, sets[i].value, prefix, sets[i].name, list);
    condition = conditions[which];
    if (!strcmp(condition, "interface")) {
      PetscCheck(coupled, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
                 "option %s interface: -general_physics %s has no interface; give the face set another condition", option,
                 side == FLUID_SIDE ? "fluid" : "structure");
      PetscCheck(!data->interface_face, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
                 "option %s: a second interface face set; the %s's interface is one face set", option,
                 side == FLUID_SIDE ? "fluid" : "structure");
      data->interface_face = sets[i].value;
      continue;
    }
    PetscCheck(data->n_dirichlet < FSIOPT_MAX_BOUNDARIES && data->n_traction < FSIOPT_MAX_BOUNDARIES,
               PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "option %s: at most %d face sets besides the interface", option,
               FSIOPT_MAX_BOUNDARIES);
    if (side == FLUID_SIDE) data->fixed_mesh_faces[data->n_fixed_mesh_faces++] = sets[i].value;
    if (!strcmp(condition, "flow")) {
      const PetscInt b = data->n_dirichlet++;
      data->dirichlet_faces[b] = sets[i].value;
      PetscCall(ReadFlowInlet(PetscOptionsObject, option, &flow_data[b]));
      data->dirichlet_fn[b]    = FlowProfileVelocity;
      data->dirichlet_ctx[b]   = flow_data[b];
      data->dirichlet_setup[b] = FlowProfileSetUp;
      continue;
    }
    if (!strcmp(condition, "wall") || !strcmp(condition, "clamped") || !strcmp(condition, "velocity")) {
      const PetscInt b = data->n_dirichlet++;
      data->dirichlet_faces[b] = sets[i].value;
      data->dirichlet_fn[b]    = FEMZero;
      if (!strcmp(condition, "velocity")) {
        PetscCall(PetscSNPrintf(datum_option, sizeof(datum_option), "%s_velocity", option));
        PetscCall(PetscOptionsString(datum_option, "the velocity there, an expression in x, y, z, t (components separated by commas)",
                                     NULL, "", text, sizeof(text), &given));
        PetscCheck(given, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
                   "option %s velocity: expected %s, the velocity as an expression in x, y, z, t", option, datum_option);
        PetscCall(ExpressionCreate(PETSC_COMM_WORLD, datum_option, text, dim, symbols, &velocity_data[b]));
        data->dirichlet_ctx[b] = velocity_data[b];
        data->dirichlet_fn[b]  = ExpressionField;
      }
      continue;
    }
    if (!strcmp(condition, "robin")) {
      PetscCall(ReadRobin(PetscOptionsObject, option, sets[i].value, data));
      continue;
    }
    if (!strcmp(condition, "resistance") || !strcmp(condition, "rcr")) {
      const PetscInt b = data->n_traction++;
      data->traction_faces[b] = sets[i].value;
      PetscCall(ReadOutlet(PetscOptionsObject, option, condition, sets[i], data, &data->traction_kernel[b]));
      continue;
    }
    {
      const PetscInt b = data->n_traction++; /* traction, pressure, open, free */
      data->traction_faces[b] = sets[i].value;
      if (strcmp(condition, "traction") && strcmp(condition, "pressure")) continue;
      PetscCall(PetscSNPrintf(datum_option, sizeof(datum_option), "%s_%s", option, condition));
      PetscCall(PetscOptionsString(datum_option, "the traction there (components separated by commas) or the pressure, "
                                   "an expression in x, y, z, t", NULL, "", text, sizeof(text), &given));
      PetscCheck(given, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "option %s %s: expected %s, an expression in x, y, z, t",
                 option, condition, datum_option);
      traction_is_pressure[side][b] = !strcmp(condition, "pressure") ? PETSC_TRUE : PETSC_FALSE;
      PetscCall(ExpressionCreate(PETSC_COMM_WORLD, datum_option, text, traction_is_pressure[side][b] ? 1 : dim,
                                 symbols, &traction_data[side][b]));
      data->traction_kernel[b] = traction_kernels[side][b];
    }
  }
  PetscOptionsEnd();
  PetscCall(CheckNoOtherFaceSets(prefix, nsets, sets));
  PetscCheck(data->interface_face || !coupled, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
             "scene general: no %s face set is the interface (-%sboundary_NAME interface)",
             side == FLUID_SIDE ? "fluid" : "structure", prefix);
  PetscFunctionReturn(0);
}

PetscErrorCode SceneCreate_General(Scene *scene)
{
  const char *const systems[] = {"nondimensional", "SI", "cgs", NULL};
  const char *const physics[] = {"fsi", "fluid", "structure", NULL};
  PetscInt          system = 0, dim = 2, nprobe = 8 * 3, which = 0;
  PetscReal         probes[8 * 3];
  PetscBool         given;
  PetscContainer    container;

  PetscFunctionBeginUser;
  PetscCall(DestroyExpressions(NULL)); /* a scene created once more starts afresh */
  PetscCall(OptionsDeclareHelpGroup("general_"));
  PetscCall(OptionsDeclareUnit("-probes_interface_displacement", UNIT_LENGTH));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene general: a case from an options file and a mesh", "scene");
  PetscCall(PetscOptionsEList("-units", "the system of units the case's values are in", NULL, systems, 3, systems[0],
                              &system, NULL));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-general_dim", "the dimension of the meshes", 2, 3, &dim));
  PetscCall(PetscOptionsEList("-general_physics",
                              "fsi: the fluid and the structure coupled on their interface; fluid, structure: one alone "
                              "(its mesh fixed, no interface)",
                              NULL, physics, 3, physics[0], &which, NULL));
  PetscCall(PetscOptionsRealArray("-probes_interface_displacement",
                                  "interface nodes x,y[,z],... whose displacement probes.csv records (dx, dy, dz)", NULL,
                                  probes, &nprobe, &given));
  PetscOptionsEnd();
  PetscCall(GeneralSymbolsLoad(&symbols));
  scene->units         = systems[system];
  scene->dim           = dim;
  scene->has_fluid     = which != 2 ? PETSC_TRUE : PETSC_FALSE;
  scene->has_structure = which != 1 ? PETSC_TRUE : PETSC_FALSE;
  if (scene->has_fluid) {
    PetscCall(ReadConditions(FLUID_SIDE, dim, which == 0, &scene->fluid));
    PetscCall(ReadBodyForce(FLUID_SIDE, dim, &scene->fluid));
    PetscCall(ReadBodyFaces(dim, &scene->fluid));
  }
  if (scene->has_structure) {
    PetscCall(ReadConditions(STRUCTURE_SIDE, dim, which == 0, &scene->structure));
    PetscCall(ReadBodyForce(STRUCTURE_SIDE, dim, &scene->structure));
  }
  if (given) {
    PetscCheck(nprobe % dim == 0 && nprobe / dim <= 8, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
               "option -probes_interface_displacement: expected up to 8 points of %" PetscInt_FMT " coordinates each",
               dim);
    scene->n_probes = nprobe / dim;
    for (PetscInt p = 0; p < scene->n_probes; ++p)
      for (PetscInt d = 0; d < dim; ++d) scene->probes[p][d] = probes[p * dim + d];
  }
  /* the expressions live as long as the run: PetscFinalize releases them */
  PetscCall(PetscContainerCreate(PETSC_COMM_SELF, &container));
  PetscCall(PetscContainerSetUserDestroy(container, DestroyExpressions));
  PetscCall(PetscObjectRegisterDestroy((PetscObject)container));
  PetscFunctionReturn(0);
}
