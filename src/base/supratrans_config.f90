!> Plain derived types that hold a validated run description: what the namelist says, after checking.
!>
!> Defaults are the paper's (Sec. 4): c = 4, N = 200, N0 = 150, kappa = 0.5, sigma = 3, dt = 0.05, T = 200,
!> Omega = 0.9. The types carry no behaviour; `supratrans_input` fills and validates them.
module supratrans_config
    use supratrans_kinds, only: wp, name_len, path_len
    use supratrans_potential, only: sine_gordon
    implicit none
    private

    !> Energy-conserving implicit scheme solved by Newton's method (paper eq. DiscreteMainDiscr).
    integer, parameter, public :: method_newton = 1
    !> Linearized scheme: G replaced by V'(u^k), one tridiagonal solve a step (paper Sec. 3.1).
    integer, parameter, public :: method_linearized = 2
    !> Classical fourth-order Runge-Kutta on the method-of-lines system (reference).
    integer, parameter, public :: method_rk4 = 3
    !> Eighth-order, 11-stage explicit Runge-Kutta method of Cooper and Verner on the same system (reference).
    integer, parameter, public :: method_rk8 = 4

    !> Default length of the linear ramp of the drive amplitude (time units); see README.
    real(wp), parameter, public :: default_ramp_time = 50.0_wp

    !> The chain of eq. (1) on N sites with the absorbing end: alpha_n = gamma + gamma'(n).
    type, public :: chain_params
        !> On-site potential: `sine_gordon` or `klein_gordon`.
        integer :: potential = sine_gordon
        !> Coupling coefficient c.
        real(wp) :: c = 4.0_wp
        !> Mass term m^2 (negative for an imaginary mass).
        real(wp) :: m2 = 0.0_wp
        !> External damping gamma.
        real(wp) :: gamma = 0.0_wp
        !> Internal damping beta.
        real(wp) :: beta = 0.0_wp
        !> Number of oscillators N.
        integer :: n = 200
        !> Last site before the absorber, N0.
        integer :: n0 = 150
        !> Absorber strength kappa: gamma'(n) rises smoothly from 0 to 2 kappa.
        real(wp) :: kappa = 0.5_wp
        !> Absorber width sigma (sites).
        real(wp) :: sigma = 3.0_wp
    end type chain_params

    !> Boundary drive u_0(t) = A r(t) sin(Omega t), r(t) = min(t / ramp_time, 1).
    type, public :: drive_params
        !> Driving amplitude A.
        real(wp) :: amplitude = 1.77_wp
        !> Driving frequency Omega.
        real(wp) :: omega = 0.9_wp
        !> Length of the linear amplitude ramp (0: no ramp).
        real(wp) :: ramp_time = default_ramp_time
    end type drive_params

    !> Time discretisation and solver controls.
    type, public :: numerics_params
        !> Integrator: `method_newton`, `method_linearized` or `method_rk4`.
        integer :: method = method_newton
        !> Time step Delta t.
        real(wp) :: dt = 0.05_wp
        !> Final time T.
        real(wp) :: t_final = 200.0_wp
        !> Newton stops when the max-norm of its update is at most this (the update is then applied).
        real(wp) :: newton_tol = 1.0e-10_wp
        !> Newton iteration cap; reaching it without convergence fails the run.
        integer :: newton_max_iter = 20
        !> A run whose |u_n| exceeds this is declared diverged (blown up).
        real(wp) :: blowup_threshold = 1.0e3_wp
    end type numerics_params

    !> What one simulation records.
    type, public :: record_params
        !> Sites n whose u_n(t) is recorded.
        integer, allocatable :: probes(:)
        !> Record probes every this many steps.
        integer :: probe_every = 1
        !> Evaluate the stored energy E_k and record the ledger every this many steps.
        integer :: ledger_every = 20
    end type record_params

    !> How a run is classified as transmitting (README, "Classification"): it transmits once an oscillator beyond
    !> the detector site n_d swings past `amplitude` (default pi, the top of the sine-Gordon barrier): the
    !> evanescent wave and the harmonic phonons stay far below it, the breathers and kinks of supratransmission
    !> go far above it.
    type, public :: detect_params
        !> Detector site n_d; 0 chooses it from linear theory: n_d = min(N0 - 10, max(20, ceiling(3/lambda))),
        !> where the evanescent wave has decayed to e^{-3} of A.
        integer :: site = 0
        !> Displacement |u_n|, n > n_d, that makes the verdict "transmitting".
        real(wp) :: amplitude = 3.141592653589793_wp
        !> Stop a run as soon as it is found transmitting (its energy totals then end at that time).
        logical :: stop_when_decided = .false.
    end type detect_params

    !> Everything one simulation needs.
    type, public :: run_config
        !> The chain.
        type(chain_params) :: chain
        !> The drive.
        type(drive_params) :: drive
        !> The numerics.
        type(numerics_params) :: numerics
        !> What to record.
        type(record_params) :: record
        !> How the run is classified.
        type(detect_params) :: detect
    end type run_config

    !> Where and how the results are written.
    type, public :: output_params
        !> Output HDF5 file.
        character(len=path_len) :: file = "supratrans.h5"
        !> Replace an existing output file instead of refusing.
        logical :: overwrite = .false.
        !> Suppress progress messages on stderr.
        logical :: quiet = .false.
    end type output_params

    !> Largest number of curves a scene may vary over (`values`), and of potentials.
    integer, parameter, public :: max_curve_values = 16

    !> The study to run and its controls.
    type, public :: scene_params
        !> Scene name: 'timeseries', 'amplitude_sweep', 'map' or 'bifurcation'.
        character(len=name_len) :: kind = "timeseries"
        !> Amplitude axis of sweeps and maps, and the search range of the bifurcation scene.
        real(wp) :: amplitude_min = 1.0_wp
        !> Upper end of the amplitude axis / search range.
        real(wp) :: amplitude_max = 3.0_wp
        !> Amplitude step of sweeps and maps.
        real(wp) :: amplitude_step = 0.01_wp
        !> Frequency axis of maps and bifurcation diagrams.
        real(wp) :: omega_min = 0.05_wp
        !> Upper end of the frequency axis.
        real(wp) :: omega_max = 1.0_wp
        !> Frequency step.
        real(wp) :: omega_step = 0.05_wp
        !> Parameter that differs between curves: 'none', 'gamma', 'beta' or 'm2'.
        character(len=name_len) :: vary = "none"
        !> Its values, one curve each (unallocated with vary = 'none').
        real(wp), allocatable :: values(:)
        !> Potentials, one panel each (default: the &chain potential).
        integer, allocatable :: potentials(:)
        !> Bifurcation search: coarse amplitude step of the upward scan.
        real(wp) :: coarse_step = 0.1_wp
        !> Bifurcation search: resolution of the threshold; stability scene: resolution of the boundary in dt.
        real(wp) :: resolution = 0.01_wp
        !> Work-precision and stability scenes: the integrators compared (`method_*`; default: all).
        integer, allocatable :: methods(:)
        !> Work-precision: the time steps (each method runs those >= its `dt_smallest`); stability: the dt axis.
        real(wp), allocatable :: dts(:)
        !> Work-precision: smallest dt run for each method, one per entry of `methods` (0: every dt of `dts`).
        real(wp), allocatable :: dt_smallest(:)
        !> Work-precision: the drive amplitudes (one set of runs each; default: the &drive amplitude).
        real(wp), allocatable :: amplitudes(:)
        !> Stability: the values of the coupling c (the c axis; default: the &chain c).
        real(wp), allocatable :: c_values(:)
        !> Work-precision: timed repetitions of each run (the median wall time is recorded).
        integer :: repeats = 3
        !> Work-precision: step of the reference solution (rk8 at reference_dt/2, checked against reference_dt).
        real(wp) :: reference_dt = 0.025_wp
    end type scene_params

    !> A whole validated input file.
    type, public :: input_config
        !> Path of the namelist file it came from.
        character(len=:), allocatable :: source
        !> The namelist text exactly as read (stored in part files, so that `merge` needs no other copy).
        character(len=:), allocatable :: text
        !> When the input was read, i.e. when the run started (ISO 8601, local time with its UTC offset).
        character(len=:), allocatable :: started
        !> Fingerprint of that text (`text_fingerprint`): ties journals and part files to the input.
        character(len=:), allocatable :: fingerprint
        !> Run only slice `slice_index` of `slice_count` of the scene's tasks (command line `--slice I/N`; 0: all).
        integer :: slice_index = 0
        !> Number of slices the scene's tasks are split into (0: not sliced).
        integer :: slice_count = 0
        !> Compute nothing: write the partial snapshot of what the journal holds (`merge --partial`).
        logical :: snapshot_only = .false.
        !> The base run (the scene varies some of its parameters).
        type(run_config) :: run
        !> The scene.
        type(scene_params) :: scene
        !> The output.
        type(output_params) :: output
        !> Allow a driving frequency outside the band gap.
        logical :: allow_outside_gap = .false.
        !> Allow parameters that violate the paper's necessary stability condition.
        logical :: allow_unstable = .false.
    end type input_config

end module supratrans_config
