/* Element matrices of a libCEED operator, computed here from libCEED's linearization of its
   pointwise function. libCEED 0.12's own CeedOperatorLinearAssemble forms B^T D B element by
   element and component pair by component pair in generic loops: on a (Q2,Q1) fluid that
   was 80 % of a Jacobian. Here the product with the output basis is one BLAS gemm over a
   chunk of elements, whose matrices go to the caller's sink while they are in cache. The
   entries come in an order of our own (element, input component, output component, input
   node, output node); FEMCeedElementPattern gives the pattern in that order. Standard
   (unoriented) restrictions with one active basis each way only. */
#include "fem_ceed.h"
#include "logging.h"
#include <petscblaslapack.h>
#include <ceed/backend.h>

typedef struct {
  CeedInt           n_elem, q, p_in, p_out, c_in, c_out, m_in, m_out;
  const CeedScalar *b_in, *b_out; /* [(q m + mode) p + node] */
} Layout;

static PetscErrorCode GetLayout(Ceed ceed, CeedOperator op, Layout *l)
{
  CeedOperatorAssemblyData data;
  CeedInt                  n_bases_in, n_bases_out, *n_modes_in, *n_modes_out;
  const CeedEvalMode     **modes_in, **modes_out;
  CeedBasis               *bases_in, *bases_out;
  const CeedScalar       **b_in, **b_out;
  CeedElemRestriction      r_in, r_out;
  CeedRestrictionType      t_in, t_out;
  CeedInt                  q_out;

  PetscFunctionBeginUser;
  PetscCallCeed(ceed, CeedOperatorGetOperatorAssemblyData(op, &data));
  PetscCallCeed(ceed, CeedOperatorAssemblyDataGetEvalModes(data, &n_bases_in, &n_modes_in, &modes_in, NULL,
                                                           &n_bases_out, &n_modes_out, &modes_out, NULL, NULL));
  PetscCheck(n_bases_in == 1 && n_bases_out == 1, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "element matrices: one active basis each way expected");
  PetscCallCeed(ceed, CeedOperatorAssemblyDataGetBases(data, NULL, &bases_in, &b_in, NULL, &bases_out, &b_out));
  PetscCallCeed(ceed, CeedOperatorGetActiveElemRestrictions(op, &r_in, &r_out));
  PetscCallCeed(ceed, CeedElemRestrictionGetType(r_in, &t_in));
  PetscCallCeed(ceed, CeedElemRestrictionGetType(r_out, &t_out));
  PetscCheck(t_in == CEED_RESTRICTION_STANDARD && t_out == CEED_RESTRICTION_STANDARD, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "element matrices: standard restrictions expected");
  PetscCheck(bases_in[0] != CEED_BASIS_NONE && bases_out[0] != CEED_BASIS_NONE, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "element matrices: active fields with a basis expected");
  PetscCallCeed(ceed, CeedElemRestrictionGetNumElements(r_in, &l->n_elem));
  PetscCallCeed(ceed, CeedElemRestrictionGetElementSize(r_in, &l->p_in));
  PetscCallCeed(ceed, CeedElemRestrictionGetElementSize(r_out, &l->p_out));
  PetscCallCeed(ceed, CeedElemRestrictionGetNumComponents(r_in, &l->c_in));
  PetscCallCeed(ceed, CeedElemRestrictionGetNumComponents(r_out, &l->c_out));
  PetscCallCeed(ceed, CeedBasisGetNumQuadraturePoints(bases_in[0], &l->q));
  PetscCallCeed(ceed, CeedBasisGetNumQuadraturePoints(bases_out[0], &q_out));
  PetscCheck(q_out == l->q, PETSC_COMM_SELF, PETSC_ERR_SUP, "element matrices: one quadrature both ways expected");
  l->m_in  = n_modes_in[0];
  l->m_out = n_modes_out[0];
  l->b_in  = b_in[0];
  l->b_out = b_out[0];
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedElementPattern(Ceed ceed, CeedOperator op, CeedSize *count, CeedInt **rows, CeedInt **cols)
{
  Layout   l;
  CeedInt *r, *c;

  PetscFunctionBeginUser;
  PetscCall(GetLayout(ceed, op, &l));
  /* libCEED's symbolic order is (element, input comp., output comp., output node, input
     node); ours swaps the last two */
  PetscCallCeed(ceed, CeedOperatorLinearAssembleSymbolic(op, count, &r, &c));
  PetscCall(PetscMalloc2(*count, rows, *count, cols));
  for (CeedSize block = 0; block < *count; block += (CeedSize)l.p_out * l.p_in) {
    for (CeedInt i = 0; i < l.p_out; ++i)
      for (CeedInt j = 0; j < l.p_in; ++j) {
        (*rows)[block + j * l.p_out + i] = r[block + i * l.p_in + j];
        (*cols)[block + j * l.p_out + i] = c[block + i * l.p_in + j];
      }
  }
  free(r);
  free(c);
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedElementMatrices(Ceed ceed, CeedOperator op, FEMCeedValuesSink sink)
{
  Layout              l;
  CeedVector          linearized   = NULL;
  CeedElemRestriction r_linearized = NULL;
  CeedInt             stride[3];
  const CeedScalar   *d;
  CeedScalar         *h, *out;
  PetscBLASInt        m_blas, k_blas, n_blas;
  const PetscScalar   one = 1.0, zero = 0.0;

  PetscFunctionBeginUser;
  PetscCall(GetLayout(ceed, op, &l));
  /* D at each point: entry ((a c_in + ci) m_out + b) c_out + co couples input mode a of
     component ci with output mode b of component co */
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CEED_LINEARIZE, 0, 0, 0, 0));
  PetscCallCeed(ceed, CeedOperatorLinearAssembleQFunctionBuildOrUpdate(op, &linearized, &r_linearized,
                                                                       CEED_REQUEST_IMMEDIATE));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CEED_LINEARIZE, 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CEED_ELEMENT_MATRICES, 0, 0, 0, 0));
  PetscCallCeed(ceed, CeedElemRestrictionGetELayout(r_linearized, &stride));
  PetscCallCeed(ceed, CeedVectorGetArrayRead(linearized, CEED_MEM_HOST, &d));
  const CeedInt k = l.q * l.m_out, rows_per_elem = l.c_in * l.c_out * l.p_in;
  PetscCall(PetscMalloc2((size_t)FEM_CEED_CHUNK_ELEMENTS * rows_per_elem * k, &h,
                         (size_t)FEM_CEED_CHUNK_ELEMENTS * rows_per_elem * l.p_out, &out));
  PetscCall(PetscBLASIntCast(k, &k_blas));
  PetscCall(PetscBLASIntCast(l.p_out, &n_blas));
  for (CeedInt e0 = 0; e0 < l.n_elem; e0 += FEM_CEED_CHUNK_ELEMENTS) {
    const CeedInt n_chunk = PetscMin(FEM_CEED_CHUNK_ELEMENTS, l.n_elem - e0);
    /* H[(e, ci, co, j)][(q, b)] = sum_a D_q[(a, ci), (b, co)] B_in[(q, a)][j] */
    for (CeedInt e = 0; e < n_chunk; ++e) {
      const CeedScalar *de = d + (CeedSize)(e0 + e) * stride[2];
      for (CeedInt q = 0; q < l.q; ++q)
        for (CeedInt ci = 0; ci < l.c_in; ++ci)
          for (CeedInt co = 0; co < l.c_out; ++co)
            for (CeedInt b = 0; b < l.m_out; ++b) {
              CeedScalar *hrow = h + ((CeedSize)((e * l.c_in + ci) * l.c_out + co) * l.p_in) * k + q * l.m_out + b;
              for (CeedInt j = 0; j < l.p_in; ++j) hrow[(CeedSize)j * k] = 0.0;
              for (CeedInt a = 0; a < l.m_in; ++a) {
                const CeedScalar
                  dv = de[q * stride[0] + (((a * l.c_in + ci) * l.m_out + b) * l.c_out + co) * stride[1]];
                const CeedScalar *bin = l.b_in + (CeedSize)(q * l.m_in + a) * l.p_in;
                if (dv == 0.0) continue;
                for (CeedInt j = 0; j < l.p_in; ++j) hrow[(CeedSize)j * k] += dv * bin[j];
              }
            }
    }
    /* values[(e, ci, co, j)][i] = sum_(q, b) H[(e, ci, co, j)][(q, b)] B_out[(q, b)][i]: in
       column-major terms values^T = B_out^T H^T */
    PetscCall(PetscBLASIntCast(n_chunk * rows_per_elem, &m_blas));
    PetscCallBLAS("BLASgemm", BLASgemm_("N", "N", &n_blas, &m_blas, &k_blas, &one, l.b_out, &n_blas, h, &k_blas, &zero,
                                        out, &n_blas));
    PetscCall(
      sink.add(sink.ctx, (CeedSize)e0 * rows_per_elem * l.p_out, (CeedSize)n_chunk * rows_per_elem * l.p_out, out));
  }
  PetscCall(PetscFree2(h, out));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CEED_ELEMENT_MATRICES, 0, 0, 0, 0));
  PetscCallCeed(ceed, CeedVectorRestoreArrayRead(linearized, &d));
  PetscCallCeed(ceed, CeedVectorDestroy(&linearized));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&r_linearized));
  PetscFunctionReturn(0);
}
