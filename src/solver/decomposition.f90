!> The domain decomposition a run on N MPI ranks would use (issue 8), as a
!> report: `xdyna --check i=deck.k parts=N`. Each element's cost is the time
!> of its element-cycle relative to a one-point hexahedron (make bench: a
!> Belytschko-Tsay shell with NIP points costs about 0.4 NIP, 2 with five
!> points; elements of rigid parts are not processed and cost 0.01), the
!> elements are split by recursive coordinate bisection of their centroids,
!> and the report gives each part's cost and the nodes it shares with other
!> parts (the halo a rank would exchange each cycle).
module xd_solver_decomposition
    use xd_kinds, only: wp
    use xd_core_strings, only: itoa
    use xd_core_partition, only: rcb_partition
    use xd_model, only: model_t, mat_rigid
    implicit none
    private
    public :: element_partition, decomposition_report

contains

    !> part(1:nhex) for the hexahedra, then part(nhex+1:) for the shells.
    subroutine element_partition(model, nparts, part, cost)
        type(model_t), intent(in) :: model
        integer, intent(in) :: nparts
        integer, allocatable, intent(out) :: part(:)
        real(wp), allocatable, intent(out) :: cost(:)
        real(wp), allocatable :: xc(:, :)
        integer :: e, n
        n = model%nhex + model%nshell
        allocate (xc(3, n), cost(n), part(n))
        do e = 1, model%nhex
            xc(:, e) = sum(model%x0(:, model%hex_conn(:, e)), 2)/8
            cost(e) = 1
            if (model%mat(model%part(model%hex_part(e))%mat_ix)%mtype == mat_rigid) cost(e) = 0.01_wp
        end do
        do e = 1, model%nshell
            xc(:, model%nhex + e) = sum(model%x0(:, model%shell_conn(:, e)), 2)/4
            associate (p => model%part(model%shell_part(e)))
                cost(model%nhex + e) = 0.4_wp*model%sec_shell(p%shell_sec_ix)%nip
                if (model%mat(p%mat_ix)%mtype == mat_rigid) cost(model%nhex + e) = 0.01_wp
            end associate
        end do
        call rcb_partition(xc, cost, nparts, part)
    end subroutine element_partition

    !> The report: per part its elements, cost (against the mean) and
    !> nodes shared with other parts; the largest imbalance and the halo.
    function decomposition_report(model, nparts) result(txt)
        type(model_t), intent(in) :: model
        integer, intent(in) :: nparts
        character(len=:), allocatable :: txt
        integer, allocatable :: part(:), owner(:), nel(:), nshared(:)
        real(wp), allocatable :: cost(:), pcost(:)
        logical, allocatable :: shared(:), seen(:)
        integer :: e, k, nd, p
        character(len=160) :: line
        call element_partition(model, nparts, part, cost)
        allocate (owner(model%nnode), shared(model%nnode), seen(model%nnode), nel(nparts), nshared(nparts), &
                  pcost(nparts))
        owner = 0
        shared = .false.
        nel = 0
        pcost = 0
        do e = 1, size(part)
            nel(part(e)) = nel(part(e)) + 1
            pcost(part(e)) = pcost(part(e)) + cost(e)
            do k = 1, merge(8, 4, e <= model%nhex)
                nd = node_of(e, k)
                if (owner(nd) == 0) then
                    owner(nd) = part(e)
                else if (owner(nd) /= part(e)) then
                    shared(nd) = .true.
                end if
            end do
        end do
        ! per part, the distinct shared nodes it has elements on
        nshared = 0
        do p = 1, nparts
            seen = .false.
            do e = 1, size(part)
                if (part(e) /= p) cycle
                do k = 1, merge(8, 4, e <= model%nhex)
                    nd = node_of(e, k)
                    if (shared(nd) .and. .not. seen(nd)) then
                        seen(nd) = .true.
                        nshared(p) = nshared(p) + 1
                    end if
                end do
            end do
        end do
        txt = ' d o m a i n   d e c o m p o s i t i o n   (recursive coordinate bisection, '//itoa(nparts)// &
              ' parts; costs relative to a one-point hexahedron)'//new_line('a')// &
              '   part   elements        cost   cost / mean   nodes shared with other parts'//new_line('a')
        do p = 1, nparts
            write (line, '(i7,i11,f12.1,f14.3,i25)') p, nel(p), pcost(p), pcost(p)/(sum(pcost)/nparts), nshared(p)
            txt = txt//trim(line)//new_line('a')
        end do
        write (line, '(a,f8.3,a,i0,a,i0,a)') '   largest cost / mean ', maxval(pcost)/(sum(pcost)/nparts), &
            '; nodes on part boundaries ', count(shared), ' of ', model%nnode, ' (the halo)'
        txt = txt//trim(line)
    contains
        !> Node k of element e (hexahedra first, then shells).
        integer function node_of(e, k)
            integer, intent(in) :: e, k
            if (e <= model%nhex) then
                node_of = model%hex_conn(k, e)
            else
                node_of = model%shell_conn(k, e - model%nhex)
            end if
        end function node_of
    end function decomposition_report

end module xd_solver_decomposition
