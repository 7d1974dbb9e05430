"""Bad input (one line 'fsiopt: error: ...' naming the culprit, non-zero exit, no summary)
and the -help listing."""
import os, shutil, subprocess

from harness import (CHANNEL, FLUID_SPACE, ROOT, turek, WORK, F, S, fail_text, fr, help_text, inputs_dir, last_rows,  # noqa: F401
                     out_dir, own_section, read_probes, refused, run, same_file, set_checkpoint_attribute, solve, test)


@test("bad input: scenes, options files, methods and models", quick=True)
def test_bad_input_choices():
    empty = os.path.join(inputs_dir(), "empty.yaml")
    open(empty, "w").close()
    return refused([
        ("unknown scene", ["-scene", "nosuchscene"], "-scene"),
        ("no scene", ["-dt", "0.1"], "-scene"),
        ("unknown coupling", F + ["-coupling", "magic"], "-coupling"),
        ("missing options file", ["-options_file", "options/nosuch.yaml"], "nosuch.yaml"),
        ("options file is a directory", ["-options_file", "options"], "-options_file"),
        ("empty options file", ["-options_file", empty], "empty.yaml"),
        ("unstable element pair", F + ["-fluid_pressure_degree", "2"], "-fluid_pressure_degree"),
        ("Dirichlet-Neumann with the convective control", CHANNEL + ["-coupling", "aitken", "-coupling_control", "convective"], "-coupling_control"),
        ("Dirichlet-Neumann on an enclosed fluid", ["-scene", "mms-stokes", "-coupling", "iqnils"], "incompressibility"),
        ("elastic projection of a St. Venant-Kirchhoff wall", ["-scene", "mms-structure", "-structure_model", "svk", "-structure_initial_projection"], "-structure_initial_projection"),
        ("unknown structure model", ["-scene", "mms-structure", "-structure_model", "neo-hookean"], "-structure_model"),
        ("too many structure ranks", ["-scene", "mms-stokes", "-structure_ranks", "3"], "-structure_ranks"),
        ("relaxed descent without Tikhonov", ["-scene", "mms-stokes", "-tao_type", "sdrelaxed"], "-coupling_tikhonov"),
        ("BDF2 with a backward-Euler forcing", F + ["-mms_discrete_time", "-fluid_time_order", "2"], "-mms_discrete_time"),
        ("third-order fluid time scheme", F + ["-fluid_time_order", "3"], "-fluid_time_order"),
        ("a case file that is not there", turek("fsi4"), "fsi4.yaml"),
        ("steady fluid on a moving mesh", turek("fsi1") + ["-fluid_steady"], "-fluid_steady"),
        ("unknown mesh motion", CHANNEL + ["-mesh_motion", "biharmonc"], "-mesh_motion. Available options: harmonic elastic biharmonic"),
        ("matrix-free fluid on PETSc's backend", F + ["-fluid_matfree", "-fem_backend", "petsc"], "-fluid_matfree"),
        ("surface force without a body", ["-scene", "mms-structure", "-probes_surface_force"], "-probes_surface_force"),
        ("lagged preconditioner of an LU fluid", CHANNEL + ["-coupling_lag_preconditioner_only"], "-coupling_lag_preconditioner_only"),
        ("first guess for an LU mesh motion", CHANNEL + ["-mesh_motion_warm_start", "1"], "-mesh_motion_warm_start"),
    ])


@test("bad input: physical parameters, time steps, tolerances")
def test_bad_input_numbers():
    return refused([
        ("a word for a number", F + ["-fluid_density", "water"], "option -fluid_density: expected a number, got 'water'"),
        ("a fraction for an integer", F + ["-refine", "1.5"], "option -refine: expected an integer"),
        ("a word for a flag", F + ["-quiet", "maybe"], "option -quiet: expected true or false"),
        ("zero fluid density", F + ["-fluid_density", "0"], "-fluid_density"),
        ("negative fluid viscosity", F + ["-fluid_viscosity", "-1"], "-fluid_viscosity"),
        ("zero viscosity", F + ["-fluid_viscosity", "0"], "-fluid_viscosity"),
        ("zero structure density", S + ["-structure_density", "0"], "-structure_density"),
        ("negative Young's modulus", S + ["-structure_youngs_modulus", "-5"], "-structure_youngs_modulus"),
        ("Poisson ratio 0.5", S + ["-structure_poisson_ratio", "0.5"], "-structure_poisson_ratio"),
        ("Poisson ratio above 0.5", S + ["-structure_poisson_ratio", "0.7"], "-structure_poisson_ratio"),
        ("zero dt", F + ["-dt", "0"], "-dt"),
        ("negative dt", F + ["-dt", "-0.01"], "-dt"),
        ("dt not dividing the interval", F + ["-dt", "0.03", "-t_start", "0", "-t_final", "0.1"], "-dt"),
        ("t_final before t_start", F + ["-t_start", "1", "-t_final", "0.5"], "-t_final"),
        ("negative refine", F + ["-refine", "-1"], "-refine"),
        ("too few extrapolation points", CHANNEL + ["-coupling_extrapolation", "2", "-coupling_extrapolation_points", "2"], "-coupling_extrapolation_points"),
        ("zero relaxation", ["-scene", "mms-stokes", "-coupling", "dn", "-coupling_omega", "0"], "-coupling_omega"),
        ("negative Tikhonov weight", ["-scene", "mms-stokes", "-coupling_tikhonov", "-1"], "-coupling_tikhonov"),
        ("zero coupling tolerance", ["-scene", "mms-stokes", "-coupling_tol", "0"], "-coupling_tol"),
        ("negative relative coupling tolerance", ["-scene", "mms-stokes", "-coupling_tol_relative", "-1"], "-coupling_tol_relative"),
        ("Newton-Krylov with a Tikhonov term", ["-scene", "mms-stokes", "-coupling_inner", "gmres", "-coupling_tikhonov", "1e-3"], "-coupling_inner"),
        ("chord step without an explicit Jacobian", ["-scene", "mms-stokes", "-coupling_inner", "chord", "-coupling_explicit_jacobian", "0"], "-coupling_inner"),
        ("unknown inner solver", ["-scene", "mms-stokes", "-coupling_inner", "cg"], "-coupling_inner"),
        ("forcing's first tolerance above 1", CHANNEL + ["-coupling_inner", "gmres", "-coupling_snes_ksp_ew_rtol0", "2"], "-coupling_snes_ksp_ew_rtol0"),
        ("chord refresh rate 1", CHANNEL + ["-fluid_chord_refresh_rate", "1"], "-fluid_chord_refresh_rate"),
        ("Schur Laplacian without a Schur split", CHANNEL + ["-fluid_schur_pressure_laplacian"], "-fluid_schur_pressure_laplacian"),
        ("Schur Laplacian of an additive split", CHANNEL + ["-fluid_schur_pressure_laplacian", "-fluid_ksp_type", "fgmres", "-fluid_pc_type", "fieldsplit"], "-fluid_schur_pressure_laplacian"),
        ("Schur Laplacian of a steady fluid", F + ["-fluid_steady", "-fluid_schur_pressure_laplacian", "-fluid_ksp_type", "fgmres", "-fluid_pc_type", "fieldsplit", "-fluid_pc_fieldsplit_type", "schur"], "-fluid_schur_pressure_laplacian"),
        ("forcing's exponent 3", CHANNEL + ["-coupling_inner", "gmres", "-coupling_snes_ksp_ew_alpha", "3"], "-coupling_snes_ksp_ew_alpha"),
        ("recurrence fitted to too few controls", CHANNEL + ["-coupling_extrapolation_points", "6", "-coupling_extrapolation_recurrence", "4"], "-coupling_extrapolation_recurrence"),
        ("recurrence fitted from more controls than recorded", CHANNEL + ["-coupling_extrapolation_recurrence_from", "13"], "-coupling_extrapolation_recurrence_from"),
        ("Taylor test at step 0", CHANNEL + ["-coupling_test_taylor", "-coupling_test_taylor_step", "0"], "-coupling_test_taylor_step"),
        ("start correction without an explicit Jacobian", ["-scene", "mms-stokes", "-coupling_start_correction", "-coupling_explicit_jacobian", "0"], "-coupling_start_correction"),
        ("sliding IMVJ window of zero steps", CHANNEL + ["-coupling", "iqnimvj", "-coupling_imvj_restart_mode", "slide"], "-coupling_imvj_restart"),
        ("negative SVD truncation", CHANNEL + ["-coupling", "iqnimvj", "-coupling_imvj_restart_mode", "svd", "-coupling_imvj_svd_truncation", "-1"], "-coupling_imvj_svd_truncation"),
        ("zero-step LS reuse", CHANNEL + ["-coupling", "iqnimvj", "-coupling_imvj_restart_mode", "ls", "-coupling_imvj_ls_reuse", "0"], "-coupling_imvj_ls_reuse"),
        ("zero -dt_min", F + ["-dt_min", "0"], "-dt_min"),
        ("negative -dt_min", F + ["-dt_min", "-1e-3"], "-dt_min"),
        ("-dt_min above -dt", F + ["-dt", "0.1", "-dt_min", "0.2"], "-dt_min"),
        ("negative mesh stiffening", turek("fsi1") + ["-mesh_motion_stiffening", "-1"], "-mesh_motion_stiffening"),
        ("negative quantities window", turek("csm1") + ["-quantities_window", "-1"], "-quantities_window"),
    ])


@test("bad input: meshes and interfaces")
def test_bad_input_meshes():
    d = inputs_dir()
    junk = os.path.join(d, "junk.msh")
    open(junk, "w").write("this is not a mesh\n")
    nolabel_geo, nolabel = os.path.join(d, "nolabels.geo"), os.path.join(d, "nolabels.msh")
    open(nolabel_geo, "w").write("Point(1)={0,0,0,0.5};Point(2)={1,0,0,0.5};Point(3)={1,1,0,0.5};Point(4)={0,1,0,0.5};"
                                 "Line(1)={1,2};Line(2)={2,3};Line(3)={3,4};Line(4)={4,1};Curve Loop(1)={1,2,3,4};"
                                 "Plane Surface(1)={1};Physical Curve(1)={1};Physical Surface(1)={1};\n")
    subprocess.run(["gmsh", "-2", "-format", "msh22", "-v", "0", "-o", nolabel, nolabel_geo], check=True, capture_output=True)
    # two quadrilaterals on the unit square with the face sets 1-4; the second listed clockwise
    inverted = os.path.join(d, "inverted.msh")
    open(inverted, "w").write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n1 0 0 0\n2 0.5 0 0\n3 1 0 0\n"
                              "4 1 1 0\n5 0.5 1 0\n6 0 1 0\n$EndNodes\n$Elements\n8\n1 1 2 1 1 1 2\n2 1 2 1 1 2 3\n"
                              "3 1 2 2 2 3 4\n4 1 2 3 3 4 5\n5 1 2 3 3 5 6\n6 1 2 4 4 6 1\n7 3 2 1 1 1 2 5 6\n"
                              "8 3 2 1 1 2 5 4 3\n$EndElements\n")
    # hostile gmsh files: PETSc's reader trusts them (a missing node gave a mesh that ran to a wrong answer)
    square = ("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n1 0 0 0\n2 0.5 0 0\n3 1 0 0\n4 1 1 0\n5 0.5 1 0\n"
              "6 0 1 0\n$EndNodes\n$Elements\n8\n1 1 2 1 1 1 2\n2 1 2 1 1 2 3\n3 1 2 2 2 3 4\n4 1 2 3 3 4 5\n"
              "5 1 2 3 3 5 6\n6 1 2 4 4 6 1\n7 3 2 1 1 1 2 5 6\n8 3 2 1 1 2 3 4 5\n$EndElements\n")
    hostile = {
        "missing-node": square.replace("8 3 2 1 1 2 3 4 5", "8 3 2 1 1 2 3 4 9"),
        "duplicated-node": square.replace("\n6\n1 0 0 0", "\n7\n1 0 0 0").replace("6 0 1 0\n", "6 0 1 0\n6 0 1 0\n"),
        "zero-node": square.replace("8 3 2 1 1 2 3 4 5", "8 3 2 1 1 2 3 4 0"),
        "wrong-count": square.replace("$Elements\n8\n", "$Elements\n9\n"),
        "crack": square.replace("\n6\n1 0 0 0", "\n7\n1 0 0 0").replace("$EndNodes", "7 0.5 0 0\n$EndNodes")
                       .replace("8 3 2 1 1 2 3 4 5", "8 3 2 1 1 7 3 4 5"),
        "volume-element": square.replace("$Elements\n8\n", "$Elements\n9\n").replace(
            "$EndElements", "9 4 2 1 1 1 2 3 4\n$EndElements"),
        "unknown-type": square.replace("8 3 2 1 1 2 3 4 5", "8 6 2 1 1 1 2 3 4 5 6"),
    }
    paths = {}
    for name, text in hostile.items():
        paths[name] = os.path.join(d, name + ".msh")
        open(paths[name], "w").write(text)
    square4 = os.path.join(d, "square41.msh")
    subprocess.run(["gmsh", "-2", "-format", "msh41", "-v", "0", "-o", square4, os.path.join(ROOT, "meshes", "square.geo")],
                   check=True, capture_output=True)
    lines = open(square4).read().split("\n")
    end = lines.index("$EndElements")
    lines[end - 1] = " ".join(lines[end - 1].split()[:-1] + ["999"])
    missing41 = os.path.join(d, "missing41.msh")
    open(missing41, "w").write("\n".join(lines))
    garbage = os.path.join(d, "garbage.msh")
    open(garbage, "wb").write(bytes((i * 37 + 11) % 256 for i in range(5000)))
    collapsed = os.path.join(d, "collapsed.msh")
    open(collapsed, "w").write(square.replace("8 3 2 1 1 2 3 4 5", "8 3 2 1 1 2 3 4 4"))
    truncated = os.path.join(d, "truncated.msh")
    open(truncated, "w").write(open(os.path.join(ROOT, "meshes", "wall.msh")).read()[:600])
    return refused([
        ("missing mesh file", F + ["-fluid_dm_plex_filename", "meshes/nosuch.msh"], "nosuch.msh"),
        ("unreadable mesh file", F + ["-fluid_dm_plex_filename", junk], "junk.msh"),
        ("mesh lacking labels", F + ["-fluid_dm_plex_filename", nolabel], "Face Sets"),
        ("mesh with an inverted cell", F + ["-fluid_dm_plex_filename", inverted], "inverted or degenerate"),
        ("truncated mesh file", S + ["-structure_dm_plex_filename", truncated], "truncated.msh"),
        ("3D mesh for a 2D scene", F + ["-fluid_dm_plex_filename", "meshes/tube3d-fluid.msh"], "is 3D"),
        ("gmsh: a cell's node missing", F + ["-fluid_dm_plex_filename", paths["missing-node"]], "refers to node 9, which $Nodes does not have"),
        ("gmsh 4.1: a cell's node missing", F + ["-fluid_dm_plex_filename", missing41], "refers to node 999"),
        ("gmsh: a node listed twice", F + ["-fluid_dm_plex_filename", paths["duplicated-node"]], "listed twice"),
        ("gmsh: node 0", F + ["-fluid_dm_plex_filename", paths["zero-node"]], "refers to node 0"),
        ("gmsh: a wrong element count", F + ["-fluid_dm_plex_filename", paths["wrong-count"]], "declares 9 elements"),
        ("gmsh: a crack", F + ["-fluid_dm_plex_filename", paths["crack"]], "a crack or a duplicated node"),
        ("gmsh: a tetrahedron in a 2D mesh", F + ["-fluid_dm_plex_filename", paths["volume-element"]], "is 3D"),
        ("gmsh: a prism", F + ["-fluid_dm_plex_filename", paths["unknown-type"]], "gmsh type 6"),
        ("gmsh: random bytes (PETSc's reader crashed)", F + ["-fluid_dm_plex_filename", garbage], "garbage.msh: not a gmsh mesh"),
        ("gmsh: a cell naming a node twice", F + ["-fluid_dm_plex_filename", collapsed], "names node 4 twice"),
        ("box without cells in a direction", F + ["-fluid_dm_plex_box_faces", "0,4"], "-fluid_dm_plex_box_faces: expected at least 1 cell"),
        ("box with its corners swapped", F + ["-fluid_dm_plex_box_lower", "1,1", "-fluid_dm_plex_box_upper", "0,0"], "-fluid_dm_plex_box_lower and -fluid_dm_plex_box_upper"),
        ("row sums as the weight of P2 triangles", ["-options_file", "options/bend3d.yaml", "-coupling_interface_lumping",
                                                    "row-sum"], "option -coupling_interface_lumping: the row sums"),
        ("non-conforming interface (counts)", ["-scene", "mms-stokes", "-structure_dm_plex_box_faces", "5,2"], "do not conform"),
        ("non-conforming interface (shifted)", ["-scene", "mms-stokes", "-structure_dm_plex_box_lower", "0.01,1", "-structure_dm_plex_box_upper", "1.01,1.5"], "fluid node (0"),
    ])


@test("bad input: restarts")
def test_bad_input_restarts():
    d = inputs_dir()
    not_hdf5 = os.path.join(d, "junk.h5")
    open(not_hdf5, "w").write("not hdf5\n")
    solve(CHANNEL + ["-t_final", "0.0002", "-checkpoint_every", "1"], out=os.path.join(d, "ck"))
    checkpoint = os.path.join(d, "ck", "checkpoint.h5")
    import h5py, numpy as np
    damaged = {}
    data = open(checkpoint, "rb").read()
    damaged["truncated"] = os.path.join(d, "ck-truncated.h5")
    open(damaged["truncated"], "wb").write(data[:len(data) // 2])
    for name in ("missing", "short", "nan", "noattr", "nofingerprint", "dtnan", "stepstring", "stateint", "state2d"):
        damaged[name] = os.path.join(d, "ck-%s.h5" % name)
        shutil.copy(checkpoint, damaged[name])
        with h5py.File(damaged[name], "a") as f:
            if name == "noattr":
                del f["run"].attrs["step"]
                continue
            if name == "nofingerprint":
                del f["run"].attrs["problem_options"]
                continue
            if name == "dtnan":   # with its checksum: what the checksum cannot see is checked too
                set_checkpoint_attribute(f, "run", "dt", np.nan)
                continue
            if name == "stepstring":
                f["run"].attrs["step"] = np.bytes_("two")
                continue
            a = np.array(f["fluid/state"])
            del f["fluid/state"]
            if name == "short":
                f["fluid/state"] = a[:len(a) // 2]
            elif name == "stateint":
                f["fluid/state"] = a.astype(np.int64)
            elif name == "state2d":
                f["fluid/state"] = a.reshape(-1, 1)
            elif name == "nan":
                a[3] = np.nan
                f["fluid/state"] = a
    clash = os.path.join(d, "clash")
    rc, stdout, err, _ = run(CHANNEL + ["-t_final", "0.0002", "-checkpoint_every", "1", "-checkpoint_file",
                                        os.path.join(clash, "probes.csv")], out=clash)
    lines = [l for l in (stdout + err).splitlines() if l.strip()]
    assert rc != 0 and len(lines) == 1 and "the name of a file the run writes" in lines[0], \
        "checkpoint file named as the run's probes.csv: exit %s, %s" % (rc, lines)
    return "checkpoint named as the run's probes.csv refused; " + refused([
        ("checkpoint truncated", CHANNEL + ["-restart", damaged["truncated"]], "truncated, or not a checkpoint"),
        ("checkpoint without a dataset", CHANNEL + ["-restart", damaged["missing"]], "has no dataset /fluid/state"),
        ("checkpoint with a mis-sized dataset", CHANNEL + ["-restart", damaged["short"]], "dataset /fluid/state has"),
        ("checkpoint with a NaN", CHANNEL + ["-restart", damaged["nan"]], "holds NaN or Inf"),
        ("checkpoint without its step", CHANNEL + ["-restart", damaged["noattr"]], "no attribute 'step'"),
        ("checkpoint without its fingerprint", CHANNEL + ["-restart", damaged["nofingerprint"], "-structure_density", "5"], "does not record the options"),
        ("checkpoint with dt NaN", CHANNEL + ["-restart", damaged["dtnan"]], "is not a positive number"),
        ("checkpoint with a string for its step", CHANNEL + ["-restart", damaged["stepstring"]], "attribute 'step' in /run holds a string"),
        ("checkpoint with integers for a state", CHANNEL + ["-restart", damaged["stateint"]], "dataset 'state' in /fluid holds an integer"),
        ("checkpoint with a state of two dimensions", CHANNEL + ["-restart", damaged["state2d"]], "dataset 'state' in /fluid has another shape"),
        ("checkpoint file is a directory", CHANNEL + ["-t_final", "0.0002", "-checkpoint_every", "1", "-checkpoint_file", d], "a directory"),
        ("restart from a file that is not HDF5", CHANNEL + ["-restart", not_hdf5], "not an HDF5 file"),
        ("restart from a missing file", CHANNEL + ["-restart", os.path.join(d, "nosuch.h5")], "-restart"),
        ("restart with another dt", CHANNEL + ["-t_final", "0.001", "-dt", "5e-5", "-restart", checkpoint], "dt"),
        ("restart of another mesh", CHANNEL + ["-t_final", "0.002", "-refine", "1", "-restart", checkpoint], "-restart"),
        ("restart past the end", CHANNEL + ["-t_final", "0.0001", "-restart", checkpoint], "-restart"),
        ("-restart_change_dt without -restart", CHANNEL + ["-restart_change_dt"], "-restart_change_dt"),
        ("new dt off the checkpoint's time", CHANNEL + ["-t_final", "0.0012", "-dt", "3e-4", "-restart", checkpoint, "-restart_change_dt"], "whole number of steps"),
        ("new dt with -write_fields", CHANNEL + ["-t_final", "0.001", "-dt", "5e-5", "-restart", checkpoint, "-restart_change_dt", "-write_fields"], "-write_fields"),
        ("restart with a renumbered fluid mesh", CHANNEL + ["-t_final", "0.001", "-restart", checkpoint, "-fluid_dm_plex_reorder", "rcm"], "another split or numbering of the fluid mesh"),
        ("restart with another density", CHANNEL + ["-t_final", "0.001", "-restart", checkpoint, "-structure_density", "2"], "written with -structure_density 1.1, this run has -structure_density 2"),
        ("restart with another coupling method", CHANNEL + ["-t_final", "0.001", "-restart", checkpoint, "-coupling", "iqnils"], "-restart_change coupling"),
        ("restart with another time scheme", CHANNEL + ["-t_final", "0.001", "-restart", checkpoint, "-fluid_time_order", "2"], "-fluid_time_order"),
        ("restart with another mesh motion", CHANNEL + ["-t_final", "0.001", "-restart", checkpoint, "-mesh_motion", "elastic"], "-mesh_motion"),
        ("restart with another Young's modulus", CHANNEL + ["-t_final", "0.001", "-restart", checkpoint, "-structure_youngs_modulus", "1e7"], "-structure_youngs_modulus"),
        ("-restart_change without -restart", CHANNEL + ["-restart_change", "structure_density"], "-restart_change"),
        ("restart with another t_start", CHANNEL + ["-t_start", "1e-4", "-t_final", "0.001", "-restart", checkpoint], "t_start"),
    ])




@test("-help lists scenes and options", quick=True)
def test_help_lists_options():
    text = help_text(["-scene", "mms-fluid"])
    for opt in ["-scene", "-coupling", "-refine", "-dt", "-t_start", "-t_final", "-output_dir", "-fluid_density",
                "-fluid_viscosity", "-fluid_model", "-mms_discrete_time", "-write_fields", "-write_fields_interval",
                "-fluid_rhs_rtol", "-fluid_extrapolate"]:
        assert opt in text, "%s not in -help" % opt
    # a coupled moving-mesh scene with a partitioned method lists the coupling's options too
    text = help_text(["-options_file", "options/channel2d.yaml", "-coupling", "iqnils"])
    for opt in ["-coupling_domain", "-coupling_predictor", "-coupling_mesh_extrapolate", "-coupling_extrapolation",
                "-coupling_extrapolation_points",
                "-coupling_omega", "-coupling_rtol", "-coupling_atol", "-coupling_iqn_reuse", "-mesh_motion",
                "-parameter_amplitude", "-fluid_boundary_left_traction", "-fluid_backflow_stabilization", "-structure_model"]:
        assert opt in text, "%s not in -help of channel2d with -coupling iqnils" % opt
    text = help_text(["-options_file", "options/channel2d.yaml", "-coupling", "iqnimvj"])
    for opt in ["-coupling_imvj_restart", "-coupling_iqn_columns", "-coupling_iqn_filter"]:
        assert opt in text, "%s not in -help of channel2d with -coupling iqnimvj" % opt
    text = help_text(turek("fsi3"))
    for opt in ["-parameter_U", "-parameter_ramp", "-fluid_body_faces", "-fluid_boundary_inflow_velocity",
                "-quantities_window", "-checkpoint_every", "-checkpoint_file", "-restart", "-fluid_steady",
                "-mesh_motion_stiffening", "-mesh_motion_incremental", "-mesh_motion_warm_start", "-dt_min",
                "-fluid_time_order", "-coupling_lag_preconditioner_only",
                "-coupling_explicit_jacobian_rebuild_its", "-interrupt_test_step", "-interrupt_test_signal", "-interrupt_test_failure",
                "-coupling_inner", "-coupling_inner_jump_fraction", "-coupling_chord_contraction",
                "-coupling_start_correction", "-coupling_extrapolation_recurrence", "-coupling_extrapolation_recurrence_from", "-coupling_secant_updates", "-coupling_tol_relative",
                "-coupling_test_taylor_step"]:
        assert opt in text, "%s not in -help of turek-hron" % opt
    # fsiopt's own options at the end, by prefix, with units in the scene's system
    groups = own_section(text)
    fluid = " ".join(groups.get("fluid_", []))
    assert "-fluid_density" in fluid and "[kg/m^3]" in fluid and "[Pa s]" in fluid, "turek-hron's fluid_ group: %s" % fluid[:300]
    assert not [l for g, lines in groups.items() if g != "the run (no prefix)" and not g.startswith("checks")
                for l in lines if not l.startswith("  -" + g)], "an option outside its group: %s" % groups
    # a scene's options: under the prefix it declares, with the units it declares
    gcl = own_section(help_text(["-scene", "gcl"]))
    assert [l for l in gcl.get("gcl_", []) if l.startswith("  -gcl_amplitude")], "gcl's groups: %s" % list(gcl)
    channel = own_section(help_text(["-options_file", "options/channel2d.yaml"]))
    assert "[g/cm^3]" in " ".join(channel.get("structure_", [])), "channel2d's structure_ group: %s" % channel.get("structure_")
    return "3 scenes' -help, no files left; fsiopt's options in %d groups with SI and cgs units" % len(groups)


@test("-help: fsiopt's options first, grouped, the checks apart; PETSc's only under -help all; -help | head -1 exits 0 in 50 runs")
def test_help_order_and_pipe():
    text = help_text(["-options_file", "options/channel2d.yaml"])
    lines = text.splitlines()
    assert lines[0].startswith("fsiopt: fluid-structure interaction"), "first line: %r" % lines[0]
    assert "Petsc Release Version" not in text and "  -fluid_ksp_type <" not in text, "-help prints PETSc's listing"
    assert "-help all" in lines[-2] or "-help all" in lines[-1], "-help does not say how to see PETSc's: %s" % lines[-2:]
    groups = own_section(text)
    checks = [g for g in groups if g.startswith("checks")]
    assert checks and all("test" in l or "check" in l for l in groups[checks[0]]), "checks group: %s" % checks
    for g, options in groups.items():
        if not g.startswith("checks"):
            assert not [l for l in options if "_test_" in l.split()[0] or "backend_check" in l.split()[0]], \
                "a check among %s's options: %s" % (g, options)
    full = help_text(["-help", "all", "-options_file", "options/channel2d.yaml"])
    own_at, petsc_at = full.find("fsiopt's options, by prefix"), full.find("  -fluid_ksp_type <")
    assert 0 <= own_at < petsc_at, "-help all: fsiopt's options at %d, PETSc's -fluid_ksp_type at %d" % (own_at, petsc_at)
    env = fr.fsiopt_env()
    bad = []
    for i in range(50):
        p = subprocess.run("%s -help -scene mms-fluid | head -1" % fr.FSIOPT, shell=True, cwd=ROOT, env=env,
                           capture_output=True, text=True, executable="/bin/bash",
                           timeout=120)
        p2 = subprocess.run(["/bin/bash", "-c", "set -o pipefail; %s -help -scene mms-fluid | head -1 >/dev/null; "
                             "echo ${PIPESTATUS[0]}" % fr.FSIOPT], cwd=ROOT, env=env, capture_output=True, text=True,
                            timeout=120) if i % 10 == 0 else None
        status = p2.stdout.strip() if p2 else "0"
        if p.returncode != 0 or p.stderr.strip() or not p.stdout.startswith("fsiopt:") or status != "0":
            bad.append((i, p.returncode, status, p.stderr.strip()[:200]))
    assert not bad, "-help | head -1: %d of 50 not quiet: %s" % (len(bad), bad[:3])
    return "%d own groups (checks apart) before PETSc's; 50 of 50 -help | head -1 quiet, fsiopt's exit 0" % len(groups)


@test("integer options past fsiopt's integers (2^32 + 1, 10^10, 10^20, -10^23) or given PETSc's words DEFAULT, DECIDE, "
      "DETERMINE: one line naming the option and its range, from the command line and from YAML, before any output")
def test_integer_overflow():
    yaml = os.path.join(inputs_dir(), "huge-refine.yaml")
    with open(yaml, "w") as f:
        f.write("refine: 4294967297\n")
    cases = [("refine 2^32 + 1", CHANNEL + ["-refine", "4294967297"], "-refine"),
             ("refine from YAML", CHANNEL + ["-options_file", yaml], "-refine"),
             ("max_it 10^10", CHANNEL + ["-coupling_max_it", "10000000000"], "-coupling_max_it"),
             ("checkpoint interval 2^32", CHANNEL + ["-checkpoint_every", "4294967296"], "-checkpoint_every"),
             ("fields interval 10^20", CHANNEL + ["-write_fields", "-write_fields_interval", "100000000000000000000"],
              "-write_fields_interval"),
             ("extrapolation -10^23", CHANNEL + ["-coupling_extrapolation", "-99999999999999999999999"],
              "-coupling_extrapolation"),
             ("box faces 2^32 + 10", CHANNEL + ["-fluid_dm_plex_box_faces", "30,4294967306"], "-fluid_dm_plex_box_faces"),
             ("backflow faces 10^11", CHANNEL + ["-fluid_backflow_faces", "99999999999"], "-fluid_backflow_faces"),
             ("test step 2^32 + 7", CHANNEL + ["-interrupt_test_step", "4294967303"], "-interrupt_test_step"),
             ("max_it DEFAULT", CHANNEL + ["-coupling_max_it", "DEFAULT"], "DEFAULT"),
             ("fields interval DECIDE", CHANNEL + ["-write_fields", "-write_fields_interval", "DECIDE"], "DECIDE"),
             ("refine determine", CHANNEL + ["-refine", "determine"], "determine"),
             ("jacobian lag PETSC_DEFAULT", CHANNEL + ["-coupling", "monolithic", "-coupling_monolithic_jacobian_lag",
                                                      "PETSC_DEFAULT"], "PETSC_DEFAULT")]
    return refused(cases)



@test("face sets the mesh or the condition lacks: -fluid_backflow_faces naming no traction boundary (a face set "
      "the mesh lacks, or a wall), -write_fields_walls naming a face-set number the mesh lacks: one line naming the "
      "option, never applied nowhere")
def test_face_sets_the_mesh_lacks():
    fields = ["-write_fields", "-write_fields_derived", "wall_shear_stress", "-write_fields_walls"]
    cases = [("backflow on a face set the mesh lacks", CHANNEL + ["-fluid_backflow_faces", "7"], "-fluid_backflow_faces"),
             ("backflow on a wall", CHANNEL + ["-fluid_backflow_faces", "1"], "traction boundaries (2, 4)"),
             ("backflow on one good, one missing", CHANNEL + ["-fluid_backflow_faces", "4,12"], "face set 12"),
             ("walls' number the mesh lacks", CHANNEL + fields + ["9"], "-write_fields_walls"),
             ("walls' name the mesh lacks", CHANNEL + fields + ["roof"], "-write_fields_walls")]
    return refused(cases)
