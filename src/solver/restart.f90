!> Restart dumps (*DATABASE_BINARY_D3DUMP, the end of a run, a stop signal,
!> the wall-clock limit): one HDF5 file, `d3dump.h5`, replaced whole each
!> time (written to a temporary file, then renamed). A restart reads the
!> deck again and builds the model as the first run did (everything that
!> does not change during a run is rebuilt, bit for bit the same), then
!> takes from the dump what changes: nodal state, element state, rigid
!> bodies and walls, contact (master node lists, per-slave history,
!> energies, search schedule), and where the output files stood. The root
!> carries the format version, the build (version, precision, compiler)
!> and the deck's fingerprint; a restart refuses a dump whose build or deck
!> differs.
module xd_solver_restart
    use hdf5
    use xd_kinds, only: wp, dp, i8
    use xd_core_strings, only: itoa
    use xd_core_files, only: rename_file, delete_file, written_bytes, file_kind, fk_missing, fk_regular
    use xd_elements_beam_bs, only: beams_t
    use xd_contact_tied, only: ties_t
    use xd_output_h5io, only: dput, dget, put_text, get_text
    use xd_solver_state, only: state_t
    use xd_elements_solid_groups, only: solids_t
    use xd_elements_shell_bt, only: shells_t
    use xd_contact_rigidwall, only: walls_t
    use xd_rigid_bodies, only: rigid_t
    use xd_contact_contact, only: contacts_t
    use xd_contact_edge_contact, only: edges_t
    use xd_output_histories, only: history_marks_t
    use xd_output_states, only: states_marks_t
    implicit none
    private
    public :: dump_meta_t, write_dump, read_dump_meta, read_dump, build_tag, dump_format

    !> 3: the slaves' clearances (list_gap) are kept; 4: the refused deep
    !> contacts (count, deepest, the segment last named per slave) and the
    !> contact's impulse and work by part pair; 5: the edge pairs of AUTOMATIC_GENERAL interfaces;
    !> 6: mass scaling; 7: a checksum of every byte after the HDF5 image, and
    !> the deck and output directory as absolute paths
    integer, parameter :: dump_format = 8
    !> what precedes the checksum at the end of a dump
    character(len=8), parameter :: sum_magic = 'XDYNASUM'

    !> What a dump says about itself.
    type :: dump_meta_t
        integer :: format = 0
        character(len=:), allocatable :: build, deck, digest, outdir
        !> read_dump_meta: what makes the file no dump to read (missing, not a
        !> regular file, failing its checksum; '' if nothing)
        character(len=:), allocatable :: damage
        real(dp) :: time = 0
        integer :: cycle = 0
    end type dump_meta_t

contains

    !> The build a dump belongs to: version, working precision, compiler.
    function build_tag() result(t)
        use, intrinsic :: iso_fortran_env, only: compiler_version
        character(len=:), allocatable :: t
        t = 'xdyna 0.1.0, real '//itoa(storage_size(1.0_wp))//' bits, '//compiler_version()
    end function build_tag

    subroutine write_dump(path, meta, st, solids, sh, bm, walls, rg, ct, td, hm, sm, ok)
        character(len=*), intent(in) :: path
        type(dump_meta_t), intent(in) :: meta
        type(state_t), intent(in) :: st
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        type(walls_t), intent(in) :: walls
        type(rigid_t), intent(in) :: rg
        type(contacts_t), intent(in) :: ct
        type(ties_t), intent(in) :: td          !< tied contacts (a tiebreak's state)
        type(beams_t), intent(in) :: bm
        type(history_marks_t), intent(in) :: hm
        type(states_marks_t), intent(in) :: sm
        logical, intent(out) :: ok
        integer(hid_t) :: f, g, r, fapl
        integer :: err, k, nf, j
        integer, allocatable :: csr(:), packed(:), ptrk(:)
        nf = 0
        call h5open_f(err)
        call h5eset_auto_f(0, err)
        ! the dump is built in memory (HDF5's core driver, no file behind
        ! it) and then written by us: a full disk or a quota fails our write,
        ! which we see and clean up, never an HDF5 file half flushed (such a
        ! file crashed HDF5's own clean-up at exit). (The newest file format,
        ! whose metadata HDF5 checksums, is not used: the image of a file
        ! still open carries its open-for-writing mark and reads back
        ! refused.)
        call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, err)
        call h5pset_fapl_core_f(fapl, 4194304_size_t, .false., err)
        call h5fcreate_f(path//'.mem', H5F_ACC_TRUNC_F, f, err, access_prp=fapl)
        call h5pclose_f(fapl, err)
        ok = err == 0
        if (.not. ok) return
        call put_text(f, 'format', itoa(dump_format))
        call put_text(f, 'build', build_tag())
        call put_text(f, 'deck', meta%deck)
        call put_text(f, 'deck_digest', meta%digest)
        call put_text(f, 'outdir', meta%outdir)
        call dput(f, 'time', [st%time], nf)
        call dput(f, 'cycle', [st%cycle], nf)

        call h5gcreate_f(f, 'state', g, err)
        call dput(g, 'x', [st%x], nf)
        call dput(g, 'v', [st%v], nf)
        if (st%rot) call dput(g, 'vr', [st%vr], nf)
        if (allocated(st%jprev)) call dput(g, 'jprev', [st%jprev], nf)
        call dput(g, 'dt', [st%dt, st%dt_old, st%dt_first], nf)
        call dput(g, 'sums', [st%dt_avg_prev, st%ext_work, st%e_initial], nf)
        call dput(g, 'crit_elem', [st%crit_elem], nf)
        if (allocated(sh%msf)) then
            ! mass scaling: the masses as they have grown, bitwise
            call dput(g, 'mass', st%mass, nf)
            if (st%rot) call dput(g, 'irot', st%irot, nf)
            call dput(g, 'ms_work', [st%ms_work], nf)
        end if
        call h5gclose_f(g, err)

        call h5gcreate_f(f, 'solids', g, err)
        call dput(g, 'sig', solids%sig, nf)
        call dput(g, 'vol', solids%vol, nf)
        call dput(g, 'qhg', solids%qhg, nf)
        call dput(g, 'qbv', solids%qbv, nf)
        call dput(g, 'epsp', solids%epsp, nf)
        call dput(g, 'alpha', solids%alpha, nf)
        call dput(g, 'eint', solids%eint, nf)
        call dput(g, 'ehg', solids%ehg, nf)
        call dput(g, 'pend_int', solids%pend_int, nf)
        call dput(g, 'pend_hg', solids%pend_hg, nf)
        if (allocated(solids%msf)) call dput(g, 'msf', solids%msf, nf)
        call h5gclose_f(g, err)

        call h5gcreate_f(f, 'shells', g, err)
        if (sh%n > 0) then
            ! (the file keeps each shell's values together, component
            ! first, as before the arrays put the element index first)
            call dput(g, 'sig', [reshape(sh%sig, [5, size(sh%sig, 3), sh%n], order=[3, 1, 2])], nf)
            call dput(g, 'qhg', [transpose(sh%qhg)], nf)
            call dput(g, 'epsp', [transpose(sh%epsp)], nf)
            if (sh%track_strain) call dput(g, 'strain', [sh%strain], nf)
            call dput(g, 'alpha', [sh%alpha], nf)
            call dput(g, 'eint', sh%eint, nf)
            call dput(g, 'ehg', sh%ehg, nf)
            call dput(g, 'pend_int', sh%pend_int, nf)
            call dput(g, 'pend_hg', sh%pend_hg, nf)
            call dput(g, 'h', sh%h, nf)
            if (allocated(sh%msf)) call dput(g, 'msf', sh%msf, nf)
        end if
        call h5gclose_f(g, err)

        call h5gcreate_f(f, 'walls', g, err)
        do k = 1, walls%n
            call dput(g, 'w'//itoa(k), [walls%w(k)%shift, walls%w(k)%vel, walls%w(k)%vel_old, walls%w(k)%energy], nf)
        end do
        call h5gclose_f(g, err)

        call h5gcreate_f(f, 'rigid', g, err)
        do k = 1, rg%n
            associate (b => rg%b(k))
                call dput(g, 'b'//itoa(k), [b%xc, b%vc, b%vc_old, b%q, b%pi, b%omega, b%omega_old, b%tfail, b%jprev], nf)
                call dput(g, 'b'//itoa(k)//'_active', [merge(1, 0, b%active)], nf)
            end associate
        end do
        call h5gclose_f(g, err)

        call h5gcreate_f(f, 'contact', g, err)
        ! a surface that erosion rebuilds: the springs' stable step it lowered
        if (ct%faces%nlatent > 0) then
            call dput(g, 'dt_limit', [ct%dt_limit], nf)
            call dput(g, 'dt_node', [ct%dt_node], nf)
        end if
        do k = 1, ct%n
            associate (it => ct%ifc(k))
                call h5gcreate_f(g, 'i'//itoa(k), r, err)
                if (allocated(it%lists%ptr)) then
                    ! the lists packed in slave order (CSR)
                    allocate (csr(size(it%lists%ptr) + 1))
                    csr(1) = 1
                    do j = 1, size(it%lists%ptr)
                        csr(j + 1) = csr(j) + it%lists%last(j) - it%lists%ptr(j) + 1
                    end do
                    allocate (packed(csr(size(csr)) - 1), ptrk(csr(size(csr)) - 1))
                    do j = 1, size(it%lists%ptr)
                        packed(csr(j):csr(j + 1) - 1) = it%lists%node(it%lists%ptr(j):it%lists%last(j))
                        ptrk(csr(j):csr(j + 1) - 1) = merge(1, 0, it%lists%trackable(it%lists%ptr(j):it%lists%last(j)))
                    end do
                    call dput(r, 'list_ptr', csr, nf)
                    call dput(r, 'list_node', packed, nf)
                    call dput(r, 'list_trackable', ptrk, nf)
                    deallocate (csr, packed, ptrk)
                    call dput(r, 'list_gap', it%lists%gap, nf)
                    call dput(r, 'list_xg', [it%lists%xg], nf)
                    call dput(r, 'list_og', it%lists%og, nf)
                    call dput(r, 'list_at', it%lists%at, nf)
                    call dput(r, 'xl', [it%xl], nf)
                end if
                call dput(r, 'ls_lc', it%ls%lc, nf)
                if (allocated(it%ls%lcodo)) call dput(r, 'ls_lcodo', it%ls%lcodo, nf)
                call dput(r, 'reals', [it%margin, it%reach, it%worst, it%pinit, it%odo], nf)
                call dput(r, 'node_drift', it%un, nf)
                call dput(r, 'class_drift', [it%uc], nf)
                call dput(r, 'class_used', it%cused, nf)
                call dput(r, 'ints', [it%last_cycle, it%nsearch, it%ninit, merge(1, 0, it%started), it%npartial], nf)
                call dput(r, 'counts', [it%total%pool, it%total%reduced, it%total%masters, it%ncontact_total, &
                                        it%nsearched], nf)
                call dput(r, 'energy', [it%energy], nf)
                call dput(r, 'cseg', it%cseg, nf)
                call dput(r, 'held', it%held, nf)
                call dput(r, 'fprev', [it%fprev], nf)
                call dput(r, 'ft', [it%ft], nf)
                call dput(r, 'p0', it%p0, nf)
                call dput(r, 'kp', it%kp, nf)
                call dput(r, 'aeff', it%aeff, nf)
                call dput(r, 'late', [it%plate], nf)
                call dput(r, 'nlate', [it%nlate], nf)
                call dput(r, 'back', [it%pback], nf)
                call dput(r, 'nback', [it%nback], nf)
                call dput(r, 'within', [it%pwithin], nf)
                call dput(r, 'nwithin', [it%nwithin], nf)
                call dput(r, 'handover', [it%phand], nf)
                call dput(r, 'nhandover', [it%nhand], nf)
                call dput(r, 'nrel', [it%nrel], nf)
                call dput(r, 'rel', [it%prel], nf)
                call dput(r, 'nref', [it%nref], nf)
                call dput(r, 'ref', [it%pref], nf)
                call dput(r, 'rlast', it%rlast, nf)
                call dput(r, 'pair_imp', [it%pair_imp], nf)
                call dput(r, 'pair_work', [it%pair_work], nf)
                ! a surface that erosion rebuilds: the search it asked for
                if (ct%faces%nlatent > 0) call dput(r, 'research', merge(1, 0, it%resl), nf)
                if (it%ed%ne > 0) then
                    ! the edge pairs of the last search and their state
                    associate (ed => it%ed)
                        call dput(r, 'edge_ints', [ed%np, ed%nlate, ed%nunknown, ed%ninit, ed%pa, ed%pb, ed%side, &
                                                   merge(1, 0, ed%named)], nf)
                        call dput(r, 'edge_reals', [ed%plate, ed%pinit, ed%kp, ed%p0, ed%dlast, [ed%ft]], nf)
                        call dput(r, 'edge_count', [ed%ncontact], nf)
                    end associate
                end if
                call h5gclose_f(r, err)
            end associate
        end do
        call h5gclose_f(g, err)

        ! eroded shells, and solids with the coordinates they are frozen on
        if (sh%n > 0) then
            if (sh%erodible) call dput(f, 'shell_dead', merge(1, 0, sh%dead), nf)
        end if
        if (solids%erodible) then
            call dput(f, 'solid_dead', merge(1, 0, solids%dead), nf)
            call dput(f, 'solid_xfrozen', [solids%xfrozen], nf)
        end if
        ! beams: resultants, section axes, internal energy
        if (bm%n > 0) then
            call dput(f, 'beam_res', [bm%res], nf)
            call dput(f, 'beam_e2', [bm%e2], nf)
            call dput(f, 'beam_eint', bm%eint, nf)
            call dput(f, 'beam_dead', merge(1, 0, bm%dead), nf)
            call dput(f, 'beam_epsp', bm%epsp, nf)
            call dput(f, 'beam_sy', bm%sy, nf)
            ! Hughes-Liu: the section points' stresses and plastic strains
            if (any(bm%hl)) then
                call dput(f, 'beam_hl_sig', [bm%hlsig], nf)
                call dput(f, 'beam_hl_ep', [bm%hlep], nf)
            end if
        end if
        ! tiebreaks: which ties broke, the softening ones' state
        if (td%n > 0) then
            call h5gcreate_f(f, 'ties', g, err)
            call dput(g, 'state', td%state, nf)
            call dput(g, 'dmg', td%dmg, nf)
            call dput(g, 'f0', [td%f0], nf)
            call dput(g, 'urel', [td%urel], nf)
            call dput(g, 'vold', [td%vold], nf)
            call dput(g, 'fs0', [td%fs0], nf)
            call dput(g, 'ework', [td%ework], nf)
            call dput(g, 'nbroken', [td%nbroken], nf)
            call h5gclose_f(g, err)
        end if

        call h5gcreate_f(f, 'output', g, err)
        call dput(g, 'hist_next', hm%next, nf)
        call dput(g, 'hist_nt', hm%nt, nf)
        call dput(g, 'hist_bytes', hm%bytes, nf)
        call dput(g, 'hist_nwritten', [hm%nwritten], nf)
        call dput(g, 'hist_rdisp', hm%rdisp, nf)
        call dput(g, 'states_n', [sm%n], nf)
        call dput(g, 'states_next', [sm%next], nf)
        call dput(g, 'states_times', sm%times, nf)
        call h5gclose_f(g, err)
        call h5fflush_f(f, H5F_SCOPE_GLOBAL_F, err)
        ok = err == 0 .and. nf == 0
        if (ok) call save_image(f, path//'.tmp', ok)
        call h5fclose_f(f, err)
        ! a failed write (a full disk, a quota) keeps the last good dump and
        ! leaves no temporary behind
        if (ok) call rename_file(path//'.tmp', path, ok)
        if (.not. ok) call delete_file(path//'.tmp')
    end subroutine write_dump

    !> Write the in-memory HDF5 file f to `path`; ok false if the system
    !> did not take every byte.
    subroutine save_image(f, path, ok)
        use, intrinsic :: iso_c_binding, only: c_loc, c_null_ptr, c_int8_t, c_ptr
        integer(hid_t), intent(in) :: f
        character(len=*), intent(in) :: path
        logical, intent(out) :: ok
        integer(size_t) :: n
        integer(c_int8_t), allocatable, target :: img(:)
        type(c_ptr) :: at
        integer :: err, u, ios
        integer(i8) :: sz
        at = c_null_ptr
        call h5fget_file_image_f(f, at, 0_size_t, err, n)
        ok = err == 0 .and. n > 0
        if (.not. ok) return
        allocate (img(n))
        at = c_loc(img)
        call h5fget_file_image_f(f, at, n, err)
        ok = err == 0
        if (.not. ok) return
        open (newunit=u, file=path, access='stream', form='unformatted', status='replace', action='write', iostat=ios)
        ok = ios == 0
        if (.not. ok) return
        ! the image, then its checksum: every byte a restart reads is covered
        ! (HDF5's own per-dataset checksums leave its metadata and the text
        ! attributes out: flipped bytes there ran another simulation, or
        ! crashed HDF5)
        write (u, iostat=ios) img, sum_magic, image_sum(img)
        ok = ios == 0
        flush (u, iostat=ios)
        inquire (unit=u, size=sz)
        ok = ok .and. ios == 0 .and. sz == int(n, i8) + 16 .and. written_bytes(u) == sz
        close (u, iostat=ios)
        ok = ok .and. ios == 0
    end subroutine save_image

    !> A checksum of bytes (Adler's two running sums, modulo 2^31 - 1, the
    !> sums reduced every 2^20 bytes so that 64 bits never overflow): b x
    !> 2^31 + a, with a = 1 + the sum of the bytes and b the sum of the a's.
    !> One changed byte always changes a.
    pure integer(i8) function image_sum(img) result(ck)
        use, intrinsic :: iso_c_binding, only: c_int8_t
        integer(c_int8_t), intent(in) :: img(:)
        integer(i8), parameter :: p = 2147483647_i8
        integer(i8) :: a, b
        integer(i8) :: i, j, n
        a = 1
        b = 0
        n = size(img, kind=i8)
        i = 1
        do while (i <= n)
            do j = i, min(n, i + 1048575_i8)
                a = a + iand(int(img(j), i8), 255_i8)
                b = b + a
            end do
            a = mod(a, p)
            b = mod(b, p)
            i = i + 1048576_i8
        end do
        ck = b*2147483648_i8 + a
    end function image_sum

    !> Whether the dump's bytes match the checksum written after them
    !> (save_image); `why` says what is wrong otherwise.
    subroutine dump_intact(path, good, why)
        use, intrinsic :: iso_c_binding, only: c_int8_t
        character(len=*), intent(in) :: path
        logical, intent(out) :: good
        character(len=:), allocatable, intent(out) :: why
        integer(c_int8_t), allocatable :: img(:)
        integer(i8) :: sz, ck
        character(len=8) :: magic
        integer :: u, ios
        good = .false.
        ! only a regular file is opened (a FIFO would block the open for ever)
        select case (file_kind(path))
        case (fk_missing)
            why = 'does not exist'
            return
        case (fk_regular)
        case default
            why = 'is not a regular file (a FIFO, a device, a socket or a directory)'
            return
        end select
        why = 'cannot be read'
        open (newunit=u, file=path, access='stream', form='unformatted', status='old', action='read', iostat=ios)
        if (ios /= 0) return
        inquire (unit=u, size=sz)
        if (sz < 16) then
            why = 'is too short to be a dump'
            close (u)
            return
        end if
        allocate (img(sz - 16))
        read (u, iostat=ios) img, magic, ck
        close (u)
        if (ios /= 0) return
        if (magic /= sum_magic) then
            why = 'has no checksum record (not an xdyna dump of this format, or cut short)'
            return
        end if
        good = ck == image_sum(img)
        why = ''
        if (.not. good) why = 'is damaged: its bytes fail the checksum written with them'
    end subroutine dump_intact

    !> The dump's own description; ok false if it is not a readable dump.
    subroutine read_dump_meta(path, meta, ok)
        character(len=*), intent(in) :: path
        type(dump_meta_t), intent(out) :: meta
        logical, intent(out) :: ok
        integer(hid_t) :: f
        integer :: err, ios
        logical :: good
        real(dp), allocatable :: t(:)
        integer, allocatable :: c(:)
        character(len=:), allocatable :: fmt
        ! every byte checked before HDF5 reads any (a damaged file crashed it)
        call dump_intact(path, good, meta%damage)
        ok = good
        if (.not. ok) return
        ! HDF5's own diagnostics stay quiet: a damaged dump is said in one line
        ! by the caller
        call h5open_f(err)
        call h5eset_auto_f(0, err)
        call h5fopen_f(path, H5F_ACC_RDONLY_F, f, err)
        ok = err == 0
        if (.not. ok) return
        fmt = get_text(f, 'format')
        read (fmt, *, iostat=ios) meta%format
        if (ios /= 0) meta%format = 0
        meta%build = get_text(f, 'build')
        meta%deck = get_text(f, 'deck')
        meta%digest = get_text(f, 'deck_digest')
        meta%outdir = get_text(f, 'outdir')
        call dget(f, 'time', t, good)
        if (good) meta%time = t(1)
        call dget(f, 'cycle', c, good)
        if (good) meta%cycle = c(1)
        call h5fclose_f(f, err)
    end subroutine read_dump_meta

    !> Put the dump's state into structures the deck has just built;
    !> `error` names what does not fit (a dump of another model).
    subroutine read_dump(path, st, solids, sh, bm, walls, rg, ct, td, hm, sm, error)
        character(len=*), intent(in) :: path
        type(state_t), intent(inout) :: st
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        type(walls_t), intent(inout) :: walls
        type(rigid_t), intent(inout) :: rg
        type(contacts_t), intent(inout) :: ct
        type(ties_t), intent(inout) :: td
        type(beams_t), intent(inout) :: bm
        type(history_marks_t), intent(out) :: hm
        type(states_marks_t), intent(out) :: sm
        character(len=:), allocatable, intent(out) :: error
        integer(hid_t) :: f, g, r
        integer :: err, k, i, j, nip
        real(wp), allocatable :: bw(:)
        real(dp), allocatable :: bd(:)
        integer, allocatable :: bi(:)
        integer(i8), allocatable :: bl(:)
        logical :: there
        call h5open_f(err)
        call h5eset_auto_f(0, err)
        call h5fopen_f(path, H5F_ACC_RDONLY_F, f, err)
        if (err /= 0) then
            error = 'cannot open the dump'
            return
        end if
        call geti(f, 'cycle', 1); if (ok()) st%cycle = bi(1)
        call getd(f, 'time', 1); if (ok()) st%time = bd(1)

        call h5gopen_f(f, 'state', g, err)
        call getw(g, 'x', size(st%x))
        if (ok()) st%x = reshape(bw, shape(st%x))
        call getw(g, 'v', size(st%v))
        if (ok()) st%v = reshape(bw, shape(st%v))
        if (st%rot) then
            call getw(g, 'vr', size(st%vr))
            if (ok()) st%vr = reshape(bw, shape(st%vr))
        end if
        call h5lexists_f(g, 'jprev', there, err)
        if (there) then
            if (.not. allocated(st%jprev)) allocate (st%jprev(3, st%nnode))
            call getw(g, 'jprev', size(st%jprev))
            if (ok()) st%jprev = reshape(bw, shape(st%jprev))
        end if
        call getw(g, 'dt', 3)
        if (ok()) then
            st%dt = bw(1)
            st%dt_old = bw(2)
            st%dt_first = bw(3)
        end if
        call getd(g, 'sums', 3)
        if (ok()) then
            st%dt_avg_prev = bd(1)
            st%ext_work = bd(2)
            st%e_initial = bd(3)
        end if
        call geti(g, 'crit_elem', 1)
        if (ok()) st%crit_elem = bi(1)
        if (allocated(sh%msf)) then
            call getw(g, 'mass', st%nnode); if (ok()) st%mass = bw
            if (st%rot) then
                call getw(g, 'irot', st%nnode); if (ok()) st%irot = bw
            end if
            call getd(g, 'ms_work', 1); if (ok()) st%ms_work = bd(1)
        end if
        call h5gclose_f(g, err)

        call h5gopen_f(f, 'solids', g, err)
        call getw(g, 'sig', size(solids%sig)); if (ok()) solids%sig = bw
        call getw(g, 'vol', size(solids%vol)); if (ok()) solids%vol = bw
        call getw(g, 'qhg', size(solids%qhg)); if (ok()) solids%qhg = bw
        call getw(g, 'qbv', size(solids%qbv)); if (ok()) solids%qbv = bw
        call getw(g, 'epsp', size(solids%epsp)); if (ok()) solids%epsp = bw
        call getw(g, 'alpha', size(solids%alpha)); if (ok()) solids%alpha = bw
        call getd(g, 'eint', size(solids%eint)); if (ok()) solids%eint = bd
        call getd(g, 'ehg', size(solids%ehg)); if (ok()) solids%ehg = bd
        call getd(g, 'pend_int', size(solids%pend_int)); if (ok()) solids%pend_int = bd
        call getd(g, 'pend_hg', size(solids%pend_hg)); if (ok()) solids%pend_hg = bd
        if (allocated(solids%msf)) then
            call getw(g, 'msf', solids%n); if (ok()) solids%msf = bw
        end if
        call h5gclose_f(g, err)

        if (sh%n > 0) then
            call h5gopen_f(f, 'shells', g, err)
            ! (in the file each shell's values together: see the writer;
            ! the rows held here are those of shells gix, every shell's on
            ! one rank)
            nip = size(sh%sig, 3)
            call getw(g, 'sig', 5*nip*sh%n)
            if (ok()) then
                do i = 1, sh%nl
                    sh%sig(i, :, :) = reshape(bw(5*nip*(sh%gix(i) - 1) + 1:5*nip*sh%gix(i)), [5, nip])
                end do
            end if
            call getw(g, 'qhg', 5*sh%n)
            if (ok()) then
                do i = 1, sh%nl
                    sh%qhg(i, :) = bw(5*(sh%gix(i) - 1) + 1:5*sh%gix(i))
                end do
            end if
            call getw(g, 'epsp', nip*sh%n)
            if (ok()) then
                do i = 1, sh%nl
                    sh%epsp(i, :) = bw(nip*(sh%gix(i) - 1) + 1:nip*sh%gix(i))
                end do
            end if
            if (sh%track_strain) then
                ! ((n, 6, nip): the shell index first)
                call getw(g, 'strain', 6*nip*sh%n)
                if (ok()) then
                    do k = 1, nip
                        do j = 1, 6
                            do i = 1, sh%nl
                                sh%strain(i, j, k) = bw(sh%gix(i) + sh%n*((j - 1) + 6*(k - 1)))
                            end do
                        end do
                    end do
                end if
            end if
            if (size(sh%alpha, 3) > 0) then
                call getw(g, 'alpha', 6*nip*sh%n)
                if (ok()) then
                    do i = 1, sh%nl
                        sh%alpha(:, :, i) = reshape(bw(6*nip*(sh%gix(i) - 1) + 1:6*nip*sh%gix(i)), [6, nip])
                    end do
                end if
            else
                call getw(g, 'alpha', 0)
            end if
            call getd(g, 'eint', sh%n); if (ok()) sh%eint = bd
            call getd(g, 'ehg', sh%n); if (ok()) sh%ehg = bd
            call getd(g, 'pend_int', sh%n); if (ok()) sh%pend_int = bd
            call getd(g, 'pend_hg', sh%n); if (ok()) sh%pend_hg = bd
            call getw(g, 'h', sh%n); if (ok()) sh%h = bw
            if (allocated(sh%msf)) then
                call getw(g, 'msf', sh%n)
                if (ok()) then
                    sh%msf = bw
                    sh%msq = sqrt(bw)
                end if
            end if
            call h5gclose_f(g, err)
        end if

        call h5gopen_f(f, 'walls', g, err)
        do k = 1, walls%n
            call getd(g, 'w'//itoa(k), 4)
            if (ok()) then
                walls%w(k)%shift = bd(1)
                walls%w(k)%vel = bd(2)
                walls%w(k)%vel_old = bd(3)
                walls%w(k)%energy = bd(4)
            end if
        end do
        call h5gclose_f(g, err)

        call h5gopen_f(f, 'rigid', g, err)
        do k = 1, rg%n
            associate (b => rg%b(k))
                call getd(g, 'b'//itoa(k), 31)
                if (ok()) then
                    b%xc = bd(1:3)
                    b%vc = bd(4:6)
                    b%vc_old = bd(7:9)
                    b%q = reshape(bd(10:18), [3, 3])
                    b%pi = bd(19:21)
                    b%omega = bd(22:24)
                    b%omega_old = bd(25:27)
                    b%tfail = bd(28)
                    b%jprev = bd(29:31)
                end if
                call geti(g, 'b'//itoa(k)//'_active', 1)
                if (ok()) b%active = bi(1) /= 0
            end associate
        end do
        call h5gclose_f(g, err)

        if (bm%n > 0) then
            call getw(f, 'beam_res', 6*bm%n); if (ok()) bm%res = reshape(bw, [6, bm%n])
            call getw(f, 'beam_e2', 3*bm%n); if (ok()) bm%e2 = reshape(bw, [3, bm%n])
            call getd(f, 'beam_eint', bm%n); if (ok()) bm%eint = bd
            call geti(f, 'beam_dead', bm%n); if (ok()) bm%dead = bi /= 0
            call getw(f, 'beam_epsp', bm%n); if (ok()) bm%epsp = bw
            call getw(f, 'beam_sy', bm%n); if (ok()) bm%sy = bw
            if (any(bm%hl)) then
                call getw(f, 'beam_hl_sig', size(bm%hlsig)); if (ok()) bm%hlsig = reshape(bw, shape(bm%hlsig))
                call getw(f, 'beam_hl_ep', size(bm%hlep)); if (ok()) bm%hlep = reshape(bw, shape(bm%hlep))
            end if
            if (.not. ok()) return
        end if
        if (sh%n > 0) then
            if (sh%erodible) then
                call geti(f, 'shell_dead', sh%n)
                if (ok()) sh%dead = bi /= 0
                if (.not. ok()) return
            end if
        end if
        if (solids%erodible) then
            call geti(f, 'solid_dead', solids%n)
            if (ok()) solids%dead = bi /= 0
            call getw(f, 'solid_xfrozen', 24*solids%n)
            if (ok()) solids%xfrozen = reshape(bw, [3, 8, solids%n])
            if (.not. ok()) return
            solids%ndead = count(solids%dead)
            solids%gdead = 0
            do k = 1, solids%n
                if (solids%dead(k)) solids%gdead(solids%group_of(k)) = solids%gdead(solids%group_of(k)) + 1
            end do
        end if
        if (td%n > 0) then
            call h5gopen_f(f, 'ties', g, err)
            if (err /= 0) then
                call fail('the model has tied contacts and the dump holds no tie state')
                return
            end if
            call geti(g, 'state', td%n); if (ok()) td%state = bi
            call getw(g, 'dmg', td%n); if (ok()) td%dmg = bw
            call getw(g, 'f0', 3*td%n); if (ok()) td%f0 = reshape(bw, [3, td%n])
            call getw(g, 'urel', 3*td%n); if (ok()) td%urel = reshape(bw, [3, td%n])
            call getw(g, 'vold', 3*td%n); if (ok()) td%vold = reshape(bw, [3, td%n])
            call getw(g, 'fs0', 3*td%n); if (ok()) td%fs0 = reshape(bw, [3, td%n])
            call getd(g, 'ework', 1); if (ok()) td%ework = bd(1)
            call geti(g, 'nbroken', 1); if (ok()) td%nbroken = bi(1)
            call h5gclose_f(g, err)
            if (.not. ok()) return
        end if
        call h5gopen_f(f, 'contact', g, err)
        if (ct%faces%nlatent > 0) then
            call getw(g, 'dt_limit', 1); if (ok()) ct%dt_limit = bw(1)
            call geti(g, 'dt_node', 1); if (ok()) ct%dt_node = bi(1)
        end if
        do k = 1, ct%n
            associate (it => ct%ifc(k), s => ct%ifc(k)%surf)
                call h5gopen_f(g, 'i'//itoa(k), r, err)
                if (err /= 0) then
                    call fail('contact interface '//itoa(k)//' is missing')
                    exit
                end if
                call h5lexists_f(r, 'list_ptr', there, err)
                if (there) then
                    call geti(r, 'list_ptr', -1)
                    if (ok()) then
                        if (size(bi) /= s%nslave + 1) call fail('contact interface '//itoa(k)// &
                                                                ' has another number of slave nodes')
                    end if
                    if (ok()) then
                        it%lists%ptr = bi(1:s%nslave)
                        it%lists%last = bi(2:s%nslave + 1) - 1
                    end if
                    call geti(r, 'list_node', -1)
                    if (ok()) then
                        it%lists%node = bi
                        it%lists%nused = size(bi)
                        it%lists%ndead = 0
                    end if
                    call geti(r, 'list_trackable', -1); if (ok()) it%lists%trackable = bi /= 0
                    call getw(r, 'list_gap', s%nslave); if (ok()) it%lists%gap = bw
                    call getw(r, 'list_xg', 3*s%nslave); if (ok()) it%lists%xg = reshape(bw, [3, s%nslave])
                    call getw(r, 'list_og', s%nslave); if (ok()) it%lists%og = bw
                    call geti(r, 'list_at', s%nslave); if (ok()) it%lists%at = bi
                    if (.not. allocated(it%xl)) allocate (it%xl(3, s%nnode))
                    call getw(r, 'xl', size(it%xl)); if (ok()) it%xl = reshape(bw, shape(it%xl))
                end if
                call getw(r, 'ls_lc', -1)
                if (ok()) it%ls%lc = bw
                call h5lexists_f(r, 'ls_lcodo', there, err)
                if (there) then
                    call getw(r, 'ls_lcodo', -1)
                    if (ok()) it%ls%lcodo = bw
                end if
                call getw(r, 'reals', 5)
                if (ok()) then
                    it%margin = bw(1)
                    it%reach = bw(2)
                    it%worst = bw(3)
                    it%pinit = bw(4)
                    it%odo = bw(5)
                end if
                call getw(r, 'node_drift', s%nnode)
                if (ok()) it%un = bw
                call getw(r, 'class_drift', size(it%uc))
                if (ok()) it%uc = reshape(bw, shape(it%uc))
                call getw(r, 'class_used', size(it%cused))
                if (ok()) it%cused = bw
                call geti(r, 'ints', 5)
                if (ok()) then
                    it%last_cycle = bi(1)
                    it%nsearch = bi(2)
                    it%ninit = bi(3)
                    it%started = bi(4) /= 0
                    it%npartial = bi(5)
                end if
                call getl(r, 'counts', 5)
                if (ok()) then
                    it%total%pool = bl(1)
                    it%total%reduced = bl(2)
                    it%total%masters = bl(3)
                    it%ncontact_total = bl(4)
                    it%nsearched = bl(5)
                end if
                call getd(r, 'energy', 1); if (ok()) it%energy = bd(1)
                call geti(r, 'cseg', size(it%cseg)); if (ok()) it%cseg = bi
                call geti(r, 'held', size(it%held)); if (ok()) it%held = bi
                if (ct%faces%nlatent > 0) then
                    call geti(r, 'research', size(it%resl)); if (ok()) it%resl = bi /= 0
                    it%resl_on = any(it%resl)
                end if
                call getw(r, 'fprev', size(it%fprev)); if (ok()) it%fprev = reshape(bw, shape(it%fprev))
                call getw(r, 'ft', size(it%ft)); if (ok()) it%ft = reshape(bw, shape(it%ft))
                call getw(r, 'p0', size(it%p0)); if (ok()) it%p0 = bw
                call getw(r, 'kp', size(it%kp)); if (ok()) it%kp = bw
                call getw(r, 'aeff', size(it%aeff)); if (ok()) it%aeff = bw
                call getw(r, 'late', 1); if (ok()) it%plate = bw(1)
                call geti(r, 'nlate', 1); if (ok()) it%nlate = bi(1)
                call getw(r, 'back', 1); if (ok()) it%pback = bw(1)
                call geti(r, 'nback', 1); if (ok()) it%nback = bi(1)
                call getw(r, 'within', 1); if (ok()) it%pwithin = bw(1)
                call geti(r, 'nwithin', 1); if (ok()) it%nwithin = bi(1)
                call getw(r, 'handover', 1); if (ok()) it%phand = bw(1)
                call geti(r, 'nhandover', 1); if (ok()) it%nhand = bi(1)
                call geti(r, 'nrel', 1); if (ok()) it%nrel = bi(1)
                call getw(r, 'rel', 1); if (ok()) it%prel = bw(1)
                call geti(r, 'nref', 1); if (ok()) it%nref = bi(1)
                call getw(r, 'ref', 1); if (ok()) it%pref = bw(1)
                call geti(r, 'rlast', size(it%rlast)); if (ok()) it%rlast = bi
                call getd(r, 'pair_imp', size(it%pair_imp)); if (ok()) it%pair_imp = reshape(bd, shape(it%pair_imp))
                call getd(r, 'pair_work', size(it%pair_work)); if (ok()) it%pair_work = reshape(bd, shape(it%pair_work))
                if (it%ed%ne > 0) call get_edges(it%ed)
                call h5gclose_f(r, err)
            end associate
        end do
        call h5gclose_f(g, err)

        call h5gopen_f(f, 'output', g, err)
        call getd(g, 'hist_next', size(hm%next)); if (ok()) hm%next = bd
        call geti(g, 'hist_nt', size(hm%nt)); if (ok()) hm%nt = bi
        call getl(g, 'hist_bytes', size(hm%bytes)); if (ok()) hm%bytes = bl
        call geti(g, 'hist_nwritten', 1); if (ok()) hm%nwritten = bi(1)
        call getd(g, 'hist_rdisp', -1); if (ok()) hm%rdisp = bd
        call geti(g, 'states_n', 1); if (ok()) sm%n = bi(1)
        call getd(g, 'states_next', 1); if (ok()) sm%next = bd(1)
        call getd(g, 'states_times', -1); if (ok()) sm%times = bd
        call h5gclose_f(g, err)
        call h5fclose_f(f, err)

    contains

        logical function ok()
            ok = .not. allocated(error)
        end function ok

        subroutine fail(text)
            character(len=*), intent(in) :: text
            if (.not. allocated(error)) error = text
        end subroutine fail

        logical function ok_size(got, want, name)
            integer, intent(in) :: got, want
            character(len=*), intent(in) :: name
            ok_size = got == want .or. want < 0
            if (.not. ok_size) call fail(name//': '//itoa(got)//' values in the dump, '//itoa(want)// &
                                         ' in the model')
            ok_size = ok_size .and. ok()
        end function ok_size

        !> Read `name` (n values, or any number if n < 0) into bw / bd / bi.
        subroutine getw(loc, name, n)
            integer(hid_t), intent(in) :: loc
            character(len=*), intent(in) :: name
            integer, intent(in) :: n
            logical :: there
            character(len=:), allocatable :: why
            if (.not. ok()) return
            call dget(loc, name, bw, there, why)
            call expect(there, size(bw), n, name, why)
        end subroutine getw

        subroutine getd(loc, name, n)
            integer(hid_t), intent(in) :: loc
            character(len=*), intent(in) :: name
            integer, intent(in) :: n
            logical :: there
            character(len=:), allocatable :: why
            if (.not. ok()) return
            call dget(loc, name, bd, there, why)
            call expect(there, size(bd), n, name, why)
        end subroutine getd

        subroutine geti(loc, name, n)
            integer(hid_t), intent(in) :: loc
            character(len=*), intent(in) :: name
            integer, intent(in) :: n
            logical :: there
            character(len=:), allocatable :: why
            if (.not. ok()) return
            call dget(loc, name, bi, there, why)
            call expect(there, size(bi), n, name, why)
        end subroutine geti

        subroutine getl(loc, name, n)
            integer(hid_t), intent(in) :: loc
            character(len=*), intent(in) :: name
            integer, intent(in) :: n
            logical :: there
            character(len=:), allocatable :: why
            if (.not. ok()) return
            call dget(loc, name, bl, there, why)
            call expect(there, size(bl), n, name, why)
        end subroutine getl

        !> The edge pairs of an AUTOMATIC_GENERAL interface (group r): np
        !> pairs, then 4 np + 4 integers and 6 np + 2 reals.
        subroutine get_edges(ed)
            type(edges_t), intent(inout) :: ed
            integer :: np, k
            call geti(r, 'edge_ints', -1)
            if (.not. ok()) return
            np = bi(1)
            if (.not. ok_size(size(bi), 4*np + 4, 'edge_ints')) return
            call getw(r, 'edge_reals', 6*np + 2)
            call getl(r, 'edge_count', 1)
            if (.not. ok()) return
            ed%np = np
            ed%nlate = bi(2)
            ed%nunknown = bi(3)
            ed%ninit = bi(4)
            ed%pa = bi(5:4 + np)
            ed%pb = bi(5 + np:4 + 2*np)
            ed%side = bi(5 + 2*np:4 + 3*np)
            ed%named = bi(5 + 3*np:4 + 4*np) /= 0
            ed%plate = bw(1)
            ed%pinit = bw(2)
            ed%kp = bw(3:2 + np)
            ed%p0 = bw(3 + np:2 + 2*np)
            ed%dlast = bw(3 + 2*np:2 + 3*np)
            ed%ft = reshape(bw(3 + 3*np:2 + 6*np), [3, np])
            ed%ncontact = bl(1)
            if (any(ed%pa < 1 .or. ed%pa > ed%ne .or. ed%pb < 1 .or. ed%pb > ed%ne)) then
                call fail('edge_ints: an edge number outside the model''s '//itoa(ed%ne)//' exterior edges')
                return
            end if
            deallocate (ed%act, ed%st, ed%fa)
            allocate (ed%act(np), ed%st(2, np), ed%fa(3, np))
            ed%nact = count(ed%dlast > 0.0_wp)
            ed%act(1:ed%nact) = pack([(k, k=1, np)], ed%dlast > 0.0_wp)
        end subroutine get_edges

        !> A dataset read must be there, whole, with the model's number of values.
        subroutine expect(there, got, n, name, why)
            logical, intent(in) :: there
            integer, intent(in) :: got, n
            character(len=*), intent(in) :: name, why
            if (.not. there) then
                call fail(name//' '//why)
            else if (.not. ok_size(got, n, name)) then
                continue
            end if
        end subroutine expect
    end subroutine read_dump

end module xd_solver_restart
