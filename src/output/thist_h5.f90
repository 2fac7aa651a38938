!> Time histories in one HDF5 file, `thist.h5`: one group per database
!> (glstat, matsum, nodout), a `time` dataset and one dataset per named
!> column, each with a `dimension` attribute (what it measures: 'energy',
!> 'length/time^2') and a `units` attribute (its unit in the deck's system
!> of *CONTROL_UNITS, '' where the deck gives none); per-entity series are
!> 2-D (time x entity) with the entity ids beside them, whose `entity`
!> attribute says what they number. The file's root carries the title,
!> the code and version, the date and the unit system. Rows are kept in memory
!> and written in blocks (series_flush: one extent and one write per column
!> for the block, then the file flushed): a row at a time cost car6 a fifth
!> of its run. The caller flushes at most a second of wall time apart, before
!> a dump and at the end, so a killed run leaves every row up to the last
!> flush readable.
module xd_output_thist_h5
    use hdf5
    use xd_kinds, only: wp, dp
    use xd_output_h5io, only: put_text
    implicit none
    private
    public :: h5file_t, h5series_t, h5_open, h5_reopen, h5_close, series_create, series_open, series_append, &
              series_flush, h5_root_attributes

    type :: h5file_t
        integer(hid_t) :: id = -1
        logical :: open = .false.
    end type h5file_t

    type :: h5series_t
        integer(hid_t) :: gid = -1
        integer :: ncol = 0, nent = 0, nt = 0
        integer(hid_t), allocatable :: dset(:)
        integer(hid_t) :: tset = -1
        integer(hid_t) :: file = -1
        logical :: bad = .false.          !< a write failed (a full disk, a quota)
        ! rows not yet written: nb of them, the last nb of the nt
        integer :: nb = 0
        real(dp), allocatable :: bt(:)          !< (cap) their times
        real(dp), allocatable :: bv(:, :, :)    !< (max(nent, 1), ncol, cap) their values
    end type h5series_t

    !> rows a series holds before it writes them (fewer for wide series:
    !> about 4 MB at most)
    integer, parameter :: block_rows = 512

contains

    subroutine h5_open(path, f, ok)
        character(len=*), intent(in) :: path
        type(h5file_t), intent(out) :: f
        logical, intent(out) :: ok
        integer :: err
        call h5open_f(err)
        ! a failed write is said once, by the run, naming the file
        call h5eset_auto_f(0, err)
        call h5fcreate_f(path, H5F_ACC_TRUNC_F, f%id, err)
        ok = err == 0
        f%open = ok
    end subroutine h5_open

    !> Open an existing file to go on appending (a restart).
    subroutine h5_reopen(path, f, ok)
        character(len=*), intent(in) :: path
        type(h5file_t), intent(out) :: f
        logical, intent(out) :: ok
        integer :: err
        call h5open_f(err)
        call h5eset_auto_f(0, err)
        call h5fopen_f(path, H5F_ACC_RDWR_F, f%id, err)
        ok = err == 0
        f%open = ok
    end subroutine h5_reopen

    !> Open the existing group `name` written by series_create, keep its
    !> first nt rows (those of the run up to a restart dump) and append
    !> after them.
    subroutine series_open(f, name, cols, nent, nt, s, ok)
        type(h5file_t), intent(in) :: f
        character(len=*), intent(in) :: name
        character(len=*), intent(in) :: cols(:)
        integer, intent(in) :: nent, nt
        type(h5series_t), intent(out) :: s
        logical, intent(out) :: ok
        integer :: err, k
        s%ncol = size(cols)
        s%nent = nent
        s%file = f%id
        s%nt = nt
        call h5gopen_f(f%id, name, s%gid, err)
        ok = err == 0
        if (.not. ok) return
        allocate (s%dset(s%ncol))
        call h5dopen_f(s%gid, 'time', s%tset, err)
        ok = ok .and. err == 0
        call cut(s%tset, 0)
        do k = 1, s%ncol
            call h5dopen_f(s%gid, trim(cols(k)), s%dset(k), err)
            ok = ok .and. err == 0
            if (err == 0) call cut(s%dset(k), nent)
        end do
    contains
        subroutine cut(ds, ne)
            integer(hid_t), intent(in) :: ds
            integer, intent(in) :: ne
            integer :: e
            if (ne > 0) then
                call h5dset_extent_f(ds, [int(ne, hsize_t), int(nt, hsize_t)], e)
            else
                call h5dset_extent_f(ds, [int(nt, hsize_t)], e)
            end if
        end subroutine cut
    end subroutine series_open

    subroutine h5_close(f, series)
        type(h5file_t), intent(inout) :: f
        type(h5series_t), intent(inout) :: series(:)
        integer :: err, i, k
        if (.not. f%open) return
        do i = 1, size(series)
            if (series(i)%gid < 0) cycle
            call series_flush(series(i))
            do k = 1, series(i)%ncol
                call h5dclose_f(series(i)%dset(k), err)
            end do
            call h5dclose_f(series(i)%tset, err)
            call h5gclose_f(series(i)%gid, err)
            series(i)%gid = -1
        end do
        call h5fclose_f(f%id, err)
        call h5close_f(err)
        f%open = .false.
    end subroutine h5_close

    !> String attributes names(k) = values(k) on the file's root.
    subroutine h5_root_attributes(f, names, values)
        type(h5file_t), intent(in) :: f
        character(len=*), intent(in) :: names(:), values(:)
        integer :: k
        do k = 1, size(names)
            call put_text(f%id, trim(names(k)), trim(values(k)))
        end do
    end subroutine h5_root_attributes

    !> A group `name` with columns `cols` (dimensions `dims`, units `units`)
    !> for `nent` entities (0: one scalar series) whose ids are `ids`, and
    !> which kind of entity they number (`entity`); time in `time_unit`.
    subroutine series_create(f, name, cols, dims, units, time_unit, nent, ids, entity, s)
        type(h5file_t), intent(in) :: f
        character(len=*), intent(in) :: name
        character(len=*), intent(in) :: cols(:), dims(:), units(:), time_unit
        integer, intent(in) :: nent
        integer, intent(in) :: ids(:)
        character(len=*), intent(in) :: entity
        type(h5series_t), intent(out) :: s
        integer :: err, k
        integer(hid_t) :: sp, ds
        integer(hsize_t) :: d1(1)
        s%ncol = size(cols)
        s%nent = nent
        s%file = f%id
        call h5gcreate_f(f%id, name, s%gid, err)
        allocate (s%dset(s%ncol))
        call make_dataset(s%gid, 'time', 0, 'time', time_unit, s%tset)
        do k = 1, s%ncol
            call make_dataset(s%gid, trim(cols(k)), nent, trim(dims(k)), trim(units(k)), s%dset(k))
        end do
        if (nent > 0) then
            d1 = nent
            call h5screate_simple_f(1, d1, sp, err)
            call h5dcreate_f(s%gid, 'ids', H5T_NATIVE_INTEGER, sp, ds, err)
            call h5dwrite_f(ds, H5T_NATIVE_INTEGER, ids(1:nent), d1, err)
            call put_text(ds, 'entity', entity)
            call h5dclose_f(ds, err)
            call h5sclose_f(sp, err)
        end if
    end subroutine series_create

    subroutine make_dataset(gid, name, nent, dim, units, ds)
        integer(hid_t), intent(in) :: gid
        character(len=*), intent(in) :: name, dim, units
        integer, intent(in) :: nent
        integer(hid_t), intent(out) :: ds
        integer(hid_t) :: sp, pl
        integer(hsize_t) :: dims(2), maxd(2), chunk(2)
        integer :: err, rank
        if (nent > 0) then
            rank = 2
            dims = [int(nent, hsize_t), 0_hsize_t]
            maxd = [int(nent, hsize_t), H5S_UNLIMITED_F]
            chunk = [int(nent, hsize_t), int(max(1, min(64, 65536/max(nent, 1))), hsize_t)]
        else
            rank = 1
            dims = [0_hsize_t, 0_hsize_t]
            maxd = [H5S_UNLIMITED_F, 0_hsize_t]
            chunk = [256_hsize_t, 0_hsize_t]
        end if
        call h5screate_simple_f(rank, dims(1:rank), sp, err, maxd(1:rank))
        call h5pcreate_f(H5P_DATASET_CREATE_F, pl, err)
        call h5pset_chunk_f(pl, rank, chunk(1:rank), err)
        call h5dcreate_f(gid, name, H5T_NATIVE_DOUBLE, sp, ds, err, pl)
        call h5pclose_f(pl, err)
        call h5sclose_f(sp, err)
        call put_text(ds, 'dimension', dim)
        call put_text(ds, 'units', units)
    end subroutine make_dataset

    !> Append one output time: values(nent or 1, ncol), kept until the
    !> block is full (then written) or the caller flushes.
    subroutine series_append(s, time, values)
        type(h5series_t), intent(inout) :: s
        real(dp), intent(in) :: time
        real(dp), intent(in) :: values(:, :)
        integer :: cap
        if (s%bad) return
        if (.not. allocated(s%bt)) then
            cap = max(1, min(block_rows, 524288/max(1, size(values))))
            allocate (s%bt(cap), s%bv(size(values, 1), s%ncol, cap))
        end if
        s%nt = s%nt + 1
        s%nb = s%nb + 1
        s%bt(s%nb) = time
        s%bv(:, :, s%nb) = values
        ! a full block is written, not flushed: the file is flushed at the
        ! pace the histories keep (a second apart; H5Fflush goes through
        ! every dataset: 1 ms each time, a fifth of car6's output time when
        ! every full block took one)
        if (s%nb == size(s%bt)) call series_flush(s, flush_file=.false.)
    end subroutine series_append

    !> Write the rows held in memory (one extent and one write per column)
    !> and flush the file (unless flush_file is false).
    subroutine series_flush(s, flush_file)
        type(h5series_t), intent(inout) :: s
        logical, intent(in), optional :: flush_file
        integer :: k, err
        if (s%nb == 0) return
        if (s%bad) then
            s%nb = 0
            return
        end if
        call write_block(s%tset, 0, s%bt(1:s%nb))
        do k = 1, s%ncol
            ! one column's rows, contiguous (entity fastest, as the file's)
            call write_block(s%dset(k), s%nent, reshape(s%bv(:, k, 1:s%nb), [size(s%bv, 1)*s%nb]))
        end do
        s%nb = 0
        if (present(flush_file)) then
            if (.not. flush_file) return
        end if
        call h5fflush_f(s%file, H5F_SCOPE_GLOBAL_F, err)
        if (err /= 0) s%bad = .true.
    contains
        subroutine write_block(ds, nent, block)
            integer(hid_t), intent(in) :: ds
            integer, intent(in) :: nent
            real(dp), intent(in) :: block(:)
            integer(hid_t) :: fs, ms
            integer(hsize_t) :: newd(2), off(2), cnt(2)
            integer :: rank, e
            if (nent > 0) then
                rank = 2
                newd = [int(nent, hsize_t), int(s%nt, hsize_t)]
                off = [0_hsize_t, int(s%nt - s%nb, hsize_t)]
                cnt = [int(nent, hsize_t), int(s%nb, hsize_t)]
            else
                rank = 1
                newd = [int(s%nt, hsize_t), 0_hsize_t]
                off = [int(s%nt - s%nb, hsize_t), 0_hsize_t]
                cnt = [int(s%nb, hsize_t), 0_hsize_t]
            end if
            call h5dset_extent_f(ds, newd(1:rank), e)
            if (e /= 0) s%bad = .true.
            call h5dget_space_f(ds, fs, e)
            call h5sselect_hyperslab_f(fs, H5S_SELECT_SET_F, off(1:rank), cnt(1:rank), e)
            call h5screate_simple_f(rank, cnt(1:rank), ms, e)
            call h5dwrite_f(ds, H5T_NATIVE_DOUBLE, block, cnt(1:rank), e, ms, fs)
            if (e /= 0) s%bad = .true.
            call h5sclose_f(ms, e)
            call h5sclose_f(fs, e)
        end subroutine write_block
    end subroutine series_flush

end module xd_output_thist_h5
