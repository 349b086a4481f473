!> The check command (`supratrans --check FILE.nml...`, `supratrans_cli`): read and validate a namelist, its output's
!> location included and whether that directory can be written (access(2)), run nothing, write nothing; for one
!> file, what the run would need on stdout.
module supratrans_cli_check
    use, intrinsic :: iso_fortran_env, only: output_unit, error_unit, int64
    use supratrans_kinds, only: wp
    !$ use omp_lib, only: omp_get_max_threads
    use supratrans_strings, only: printable, int_str, fixed1
    use supratrans_error, only: error_type, fatal_error, err_io
    use supratrans_config, only: input_config
    use supratrans_system, only: path_kind, path_directory, path_missing, directory_writable
    use supratrans_input, only: read_input
    use supratrans_validate, only: input_warnings
    use supratrans_limits, only: run_memory_bytes
    use supratrans_scene, only: scene_type, scene_plan, new_scene
    use supratrans_tasks, only: run_work
    use supratrans_cli_output, only: check_output_location
    implicit none
    private

    public :: check_file

    !> Wall time (s) of one Newton oscillator-step on one core, release build, with the observers: the sweep of
    !> docs/benchmark.md ("Time and memory": 100 runs of N = 200, T = 200 in 4.63 s), for the estimate of --check.
    real(wp), parameter :: seconds_per_site_step = 6.0e-8_wp

contains

    !> `--check`: read and validate the namelist (output location included), run nothing, write nothing.
    subroutine check_file(path, status, error, report)
        !> Namelist file.
        character(len=*), intent(in) :: path
        !> Exit status.
        integer, intent(out) :: status
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Print the output, overwrite and memory estimate (`check_report`) when the file is fine; default false.
        logical, intent(in), optional :: report
        type(input_config) :: cfg
        character(len=:), allocatable :: warnings(:)
        integer :: i

        status = 0
        call read_input(path, cfg, error)
        if (.not. allocated(error)) then
            warnings = input_warnings(cfg)   ! the lines the run says too
            do i = 1, size(warnings)
                write (error_unit, "(a)") printable(warnings(i))
            end do
        end if
        if (.not. allocated(error)) call check_output_location(cfg, error, create=.false.)
        if (.not. allocated(error)) call check_output_writable(cfg, error)
        if (allocated(error)) status = error%stat
        if (.not. allocated(error) .and. present(report)) then
            if (report) call check_report(cfg)
        end if
    end subroutine check_file

    !> What `--check` of one file says on stdout, one "key value" a line, for scripts (input/slurm/submit.sh): the
    !> output file (`output`), whether an existing one is replaced (`overwrite` 1/0), the scene (`scene`) and the
    !> memory one run needs (`memory_per_thread_bytes`: its state, and for a timeseries its records; a scene's
    !> threads each hold one run; with checkpoints on, the checkpoint's buffers too, `checkpoint_bytes`); then what
    !> it runs, from the model's sizes (`plan` of the scene): `tasks` and `task_kind` (runs, searches, ...), and
    !> where the steps are known `runs` (a search's: the most it may ask), `steps_per_run`, `work_newton_site_steps`
    !> (runs x steps x N x the method's cost per step relative to a Newton step, `run_work`), `threads` and
    !> `estimate_seconds` (that work at `seconds_per_site_step`, over the threads: an order of magnitude); and one
    !> line for a person, `estimate ...`. A scene whose tasks are not runs of one length (continuation, stability,
    !> work_precision) gives its own work in Newton oscillator-steps (`scene_plan%work`) and what it counts, which
    !> the line says.
    subroutine check_report(cfg)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        real(wp) :: bytes, checkpoint, runs, work, seconds, per_step
        class(scene_type), allocatable :: scene
        type(error_type), allocatable :: error
        type(scene_plan) :: p
        logical :: one_run
        integer :: threads
        character(len=:), allocatable :: at_most

        one_run = .false.
        call new_scene(trim(cfg%scene%kind), scene, error)   ! validated: the kind is known
        if (.not. allocated(error)) one_run = scene%one_run()
        bytes = run_memory_bytes(cfg, one_run)   ! one run (a timeseries) holds its records too
        ! a mid-run checkpoint assembles the run's state (its levels and records, at most what the run holds) in one
        ! buffer and then the file's bytes in a second (supratrans_checkpoint); a resume reads it back the same way
        checkpoint = 0.0_wp
        if (cfg%output%checkpoint_every > 0.0_wp) checkpoint = 2.0_wp*bytes
        write (output_unit, "(a)") "output " // printable(trim(cfg%output%file))
        write (output_unit, "(a, i0)") "overwrite ", merge(1, 0, cfg%output%overwrite)
        write (output_unit, "(a)") "scene " // trim(cfg%scene%kind)
        write (output_unit, "(a, i0)") "memory_per_thread_bytes ", nint(min(bytes + checkpoint, 9.0e18_wp), int64)
        write (output_unit, "(a, i0)") "checkpoint_bytes ", nint(min(checkpoint, 9.0e18_wp), int64)
        if (allocated(error)) return
        p = scene%plan(cfg)
        if (.not. (p%tasks > 0.0_wp)) return
        write (output_unit, "(a, i0)") "tasks ", nint(min(p%tasks, 9.0e18_wp), int64)
        write (output_unit, "(a)") "task_kind " // p%noun
        threads = 1
        !$ if (.not. one_run) threads = omp_get_max_threads()
        threads = max(1, min(threads, nint(min(p%tasks, 1.0e9_wp))))   ! no more threads at work than tasks
        if (p%work > 0.0_wp) then       ! the scene counts its own work (its tasks are not runs of one length)
            if (p%serial) threads = 1
            if (.not. allocated(p%counts)) p%counts = "the scene's own count"
            if (p%runs_per_task > 0.0_wp) write (output_unit, "(a, i0)") "runs ", &
                nint(min(p%tasks*p%runs_per_task, 9.0e18_wp), int64)
            seconds = p%work*seconds_per_site_step/real(threads, wp)
            write (output_unit, "(a, es10.3)") "work_newton_site_steps ", p%work
            write (output_unit, "(a, i0)") "threads ", threads
            write (output_unit, "(a, es10.3)") "estimate_seconds ", seconds
            write (output_unit, "(a)") "estimate " // int_str(nint(min(p%tasks, 2.0e9_wp))) // " " // p%noun &
                // " (" // p%counts // "): about " // duration(seconds) // " on " // int_str(threads) &
                // " thread(s) (release build, " // int_str(nint(seconds_per_site_step*1.0e9_wp)) &
                // " ns per Newton oscillator-step; an order of magnitude)"
            return
        end if
        if (.not. (p%steps > 0.0_wp)) then
            write (output_unit, "(a)") "estimate " // int_str(nint(min(p%tasks, 2.0e9_wp))) // " " // p%noun &
                // " (their cost is not estimated)"
            return
        end if
        ! the method's cost per step and site relative to a Newton step (run_work of the input's run)
        per_step = run_work(cfg%run)/(real(max(cfg%run%chain%n, 1), wp) &
                                      *max(cfg%run%numerics%t_final/cfg%run%numerics%dt, 1.0_wp))
        runs = p%tasks*p%runs_per_task
        work = runs*p%steps*real(cfg%run%chain%n, wp)*per_step
        seconds = work*seconds_per_site_step/real(threads, wp)
        write (output_unit, "(a, i0)") "runs ", nint(min(runs, 9.0e18_wp), int64)
        write (output_unit, "(a, i0)") "steps_per_run ", nint(min(p%steps, 9.0e18_wp), int64)
        write (output_unit, "(a, es10.3)") "work_newton_site_steps ", work
        write (output_unit, "(a, i0)") "threads ", threads
        write (output_unit, "(a, es10.3)") "estimate_seconds ", seconds
        at_most = ""
        if (p%runs_per_task > 1.0_wp) at_most = " (at most " // int_str(nint(min(runs, 2.0e9_wp))) // " runs)"
        write (output_unit, "(a)") "estimate " // int_str(nint(min(p%tasks, 2.0e9_wp))) // " " // p%noun // at_most &
            // " of " // int_str(nint(min(p%steps, 2.0e9_wp))) // " steps x N = " // int_str(cfg%run%chain%n) &
            // ": about " // duration(seconds) // " on " &
            // int_str(threads) // " thread(s) (release build, " // int_str(nint(seconds_per_site_step*1.0e9_wp)) &
            // " ns per Newton oscillator-step)"
    end subroutine check_report

    !> A duration for a person: seconds, minutes, hours or days, one decimal.
    pure function duration(seconds) result(text)
        !> Seconds.
        real(wp), intent(in) :: seconds
        character(len=:), allocatable :: text

        if (seconds < 0.1_wp) then
            text = "0.1 s or less"
        else if (seconds < 120.0_wp) then
            text = fixed1(seconds) // " s"
        else if (seconds < 7200.0_wp) then
            text = fixed1(seconds/60.0_wp) // " min"
        else if (seconds < 172800.0_wp) then
            text = fixed1(seconds/3600.0_wp) // " h"
        else
            text = fixed1(seconds/86400.0_wp) // " days"
        end if
    end function duration


    !> `--check`: whether the output could be created where it is named: the nearest directory of its path that
    !> exists (the others would be made in it) must let this process create files, asked with access(2) W_OK | X_OK,
    !> which also sees a read-only mount. Nothing is created. Status 4 (as the run itself would end) when not.
    subroutine check_output_writable(cfg, error)
        !> The input.
        type(input_config), intent(in) :: cfg
        !> Error (status 4), allocated when the directory cannot be written.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: file, dir, reason
        integer :: k

        file = trim(cfg%output%file)
        k = index(file, "/", back=.true.)
        dir = "."
        if (k == 1) dir = "/"
        if (k > 1) dir = file(1:k - 1)
        do while (path_kind(dir) == path_missing .and. dir /= "." .and. dir /= "/")
            k = index(dir, "/", back=.true.)
            if (k == 0) then
                dir = "."
            else if (k == 1) then
                dir = "/"
            else
                dir = dir(1:k - 1)
            end if
        end do
        if (path_kind(dir) /= path_directory) then
            call fatal_error(error, cfg%source // ": &output: file = '" // file // "': '" // dir // "' is not a " &
                             // "directory", err_io)
        else if (.not. directory_writable(dir, reason)) then
            call fatal_error(error, cfg%source // ": &output: file = '" // file // "': cannot create files in " &
                             // "directory '" // dir // "' (access(2) W_OK: " // reason // ")", err_io)
        end if
    end subroutine check_output_writable

end module supratrans_cli_check
