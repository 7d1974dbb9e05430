/* Checks that J h is the derivative of F and J^T rho its adjoint (-coupling_test_adjoint,
   -coupling_test_taylor): a wrong sign or a stale factor would otherwise show only as a
   slower Gauss-Newton convergence, on any scene. */
#include "problem_impl.h"
#include "options.h"

static PetscErrorCode RandomVector(Vec v, unsigned long seed)
{
  PetscRandom rnd;

  PetscFunctionBeginUser;
  PetscCall(PetscRandomCreate(PetscObjectComm((PetscObject)v), &rnd));
  PetscCall(PetscRandomSetInterval(rnd, -1.0, 1.0));
  PetscCall(PetscRandomSetSeed(rnd, seed));
  PetscCall(PetscRandomSeed(rnd));
  PetscCall(VecSetRandom(v, rnd));
  PetscCall(PetscRandomDestroy(&rnd));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemTestAdjoint(CouplingProblem P, Vec x)
{
  Vec         h, rho, Jh, Jtr, a, b;
  PetscScalar lhs, rhs, scale;

  PetscFunctionBeginUser;
  /* the identity of the Jacobian the run itself takes at x (its lag counts this update
     once, and the run's own request at the same x returns), so that the check does not
     change the run; a fresh one only when the run would take none (a start already converged) */
  PetscCall(CouplingProblemUpdateJacobian(P, x));
  if (!P->jacobian_valid) PetscCall(CouplingProblemRefreshJacobian(P, x));
  PetscCall(VecDuplicate(x, &h));
  PetscCall(VecDuplicate(x, &rho));
  PetscCall(VecDuplicate(x, &Jh));
  PetscCall(VecDuplicate(x, &Jtr));
  PetscCall(RandomVector(h, 11));
  PetscCall(RandomVector(rho, 23));
  PetscCall(CouplingProblemJacobianMult(P, h, Jh));
  PetscCall(CouplingProblemJacobianMultTranspose(P, rho, Jtr));
  PetscCall(VecDot(Jh, rho, &lhs));
  PetscCall(VecDot(h, Jtr, &rhs));
  PetscCall(VecDuplicate(x, &a));
  PetscCall(VecDuplicate(x, &b));
  PetscCall(VecCopy(Jh, a));
  PetscCall(VecAbs(a));
  PetscCall(VecCopy(rho, b));
  PetscCall(VecAbs(b));
  PetscCall(VecDot(a, b, &scale));
  PetscCall(PetscPrintf(P->comm, "adjoint test: <J h, r> = %.16e  <h, J^T r> = %.16e  relative difference %.3e\n",
                        (double)PetscRealPart(lhs), (double)PetscRealPart(rhs),
                        (double)(PetscAbsScalar(lhs - rhs) / PetscRealPart(scale))));
  PetscCall(VecDestroy(&h));
  PetscCall(VecDestroy(&rho));
  PetscCall(VecDestroy(&Jh));
  PetscCall(VecDestroy(&Jtr));
  PetscCall(VecDestroy(&a));
  PetscCall(VecDestroy(&b));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemTestTaylor(CouplingProblem P, Vec x, Vec direction)
{
  Vec       h, F0, Jh, Ft, xt;
  PetscReal t = 1.0, previous = 0, hnorm, xnorm, jhnorm;
  PetscInt  n = 6;

  PetscFunctionBeginUser;
  PetscOptionsBegin(P->comm, NULL, "Taylor test", "coupling");
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-coupling_test_taylor_t0",
                                "largest step t of the Taylor test, relative to max(||x||, 1)", &t));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_test_taylor_steps", "halvings of t in the Taylor test", 2,
                              30, &n));
  PetscOptionsEnd();
  PetscCall(VecDuplicate(x, &h));
  PetscCall(VecDuplicate(x, &F0));
  PetscCall(VecDuplicate(x, &Jh));
  PetscCall(VecDuplicate(x, &Ft));
  PetscCall(VecDuplicate(x, &xt));
  hnorm = 0;
  if (direction) {
    PetscCall(VecCopy(direction, h));
    PetscCall(VecNorm(h, NORM_2, &hnorm));
  }
  if (hnorm == 0) { /* no direction, or a start that did not move */
    PetscCall(RandomVector(h, 37));
    PetscCall(VecNorm(h, NORM_2, &hnorm));
  }
  PetscCall(VecNorm(x, NORM_2, &xnorm));
  PetscCall(VecScale(h, PetscMax(xnorm, 1.0) / hnorm));
  PetscCall(CouplingProblemRefreshJacobian(P, x));
  PetscCall(CouplingProblemResidual(P, x, F0));
  PetscCall(CouplingProblemJacobianMult(P, h, Jh));
  PetscCall(VecNorm(Jh, NORM_2, &jhnorm));
  /* the first-order term beside each remainder: a remainder of fixed ratio 2 against it
     measures how far J is from the derivative (on moving domains, the neglected shape
     derivative) */
  for (PetscInt k = 0; k < n; ++k, t *= 0.5) {
    PetscReal remainder;

    PetscCall(VecWAXPY(xt, t, h, x));
    PetscCall(CouplingProblemResidual(P, xt, Ft));
    PetscCall(VecAXPY(Ft, -1.0, F0));
    PetscCall(VecAXPY(Ft, -t, Jh));
    PetscCall(VecNorm(Ft, NORM_2, &remainder));
    if (k)
      PetscCall(PetscPrintf(P->comm,
                            "Taylor test: t = %.4e  ||F(x+th) - F(x) - t J h|| = %.6e  ||t J h|| = %.6e  ratio %.4f\n",
                            (double)t, (double)remainder, (double)(t * jhnorm), (double)(previous / remainder)));
    else
      PetscCall(PetscPrintf(P->comm, "Taylor test: t = %.4e  ||F(x+th) - F(x) - t J h|| = %.6e  ||t J h|| = %.6e\n",
                            (double)t, (double)remainder, (double)(t * jhnorm)));
    previous = remainder;
  }
  PetscCall(CouplingProblemEnsureState(P, x));
  PetscCall(VecDestroy(&h));
  PetscCall(VecDestroy(&F0));
  PetscCall(VecDestroy(&Jh));
  PetscCall(VecDestroy(&Ft));
  PetscCall(VecDestroy(&xt));
  PetscFunctionReturn(0);
}
