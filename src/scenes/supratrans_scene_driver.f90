!> The driver of every scene (`run_scene`, the binding `run` of `scene_type`): the one skeleton the scenes of tasks
!> share, written once. A one-run scene (a timeseries) runs by its own `run_one`.
!>
!> A submodule of `supratrans_scene`: it uses the task engine, which the modules that validate an input (and ask the
!> abstract scene) do not.
submodule(supratrans_scene) supratrans_scene_driver
    use, intrinsic :: iso_fortran_env, only: error_unit, int64
    use supratrans_error, only: err_input, err_io
    use supratrans_invocation, only: engine_only
    use supratrans_tasks, only: run_tasks, input_fingerprint
    use supratrans_system, only: remove_own_file
    implicit none

contains

    !> Run the scene `cfg` describes and write `cfg%output%file`. A scene of tasks: refuse an existing output
    !> without overwrite; make the tasks (`make_tasks`) and print the scene's first line; run them on the task engine
    !> (`run_tasks`: resumed from the journal `<output>.journal`, a slice's part file, a merge's records); return
    !> there when the engine alone writes this invocation's output (a slice, a snapshot); else write the output
    !> (`write_output`) with the wall time (for a merge, the slices' summed wall time), delete the journal (unless
    !> `keep_journal`) and the partial file `<output>.partial.h5`, and print the scene's `summary`.
    module procedure run_scene
        type(scene_tasks) :: tasks
        character(len=:), allocatable :: output, journal, text
        integer(int64) :: clock_start, clock_end, clock_rate
        logical :: exists, keep

        if (present(inv)) tasks%inv = inv
        if (self%one_run()) then
            call self%run_one(cfg, tasks%inv, error)
            return
        end if
        call system_clock(clock_start, clock_rate)
        keep = .false.
        if (present(keep_journal)) keep = keep_journal
        output = trim(cfg%output%file)
        journal = output // ".journal"
        inquire (file=output, exist=exists)
        if (exists .and. .not. cfg%output%overwrite) then
            call fatal_error(error, output // ": output file exists (set overwrite = .true. to replace it)", err_input)
            return
        end if

        call self%make_tasks(cfg, tasks, error)
        if (allocated(error)) return
        if (.not. cfg%output%quiet .and. allocated(tasks%header)) then
            write (error_unit, "(a)") tasks%header
            flush (error_unit)
        end if
        call run_tasks(tasks%list, tasks%count, tasks%fields, journal, input_fingerprint(cfg), tasks%label, &
                       cfg%output%quiet, tasks%results, tasks%done, error, cfg, tasks%inv)
        if (allocated(error) .or. engine_only(tasks%inv)) return
        if (.not. all(tasks%done)) then
            call fatal_error(error, output // ": the task engine returned with " // tasks%label // " missing", err_io)
            return
        end if

        call system_clock(clock_end)
        tasks%elapsed = real(clock_end - clock_start, wp)/real(clock_rate, wp)
        if (tasks%inv%merge_wall_time >= 0.0_wp) tasks%elapsed = tasks%inv%merge_wall_time   ! a merge: the slices' cost
        call self%write_output(cfg, tasks, error)
        if (allocated(error)) return
        if (.not. keep) call remove_own_file(journal)
        call remove_own_file(output // ".partial.h5")
        if (.not. cfg%output%quiet) then
            text = self%summary(cfg, tasks)
            if (len(text) > 0) write (error_unit, "(a)") text
            if (tasks%inv%merge_wall_time >= 0.0_wp) write (error_unit, "(a)") "  (merged: the counts above are the " &
                // "parts' records, a time is the slices' summed wall time; nothing was run here)"
            flush (error_unit)
        end if
    end procedure run_scene

end submodule supratrans_scene_driver
