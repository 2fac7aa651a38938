!> The segment contact check (section 5.2) against closed forms: projections
!> on a flat, a warped (z = c xi eta) and a triangular segment; line and point
!> contact outside; Eqs. (8)-(11) on shell and solid masters; the return
!> direction continuous across a shell edge and around a corner.
program test_contact_segment_check
    use xd_kinds, only: wp, dp
    use xd_testing, only: check, check_close, test_summary
    use xd_contact_segment_check, only: hit_t, segment_check, contact_interior, contact_line, contact_point
    implicit none
    real(wp) :: sq(3, 4), warp(3, 4), tri(3, 4), tn(4), p(3), nrm(3), c, s0(3)
    type(hit_t) :: h, h1, h2
    real(wp), parameter :: tol = 1.0e-10_wp

    ! flat square [-1,1]^2 at z = 0, counter-clockwise seen from +z
    sq = reshape([-1.0_wp, -1.0_wp, 0.0_wp, 1.0_wp, -1.0_wp, 0.0_wp, 1.0_wp, 1.0_wp, 0.0_wp, -1.0_wp, 1.0_wp, 0.0_wp], &
                 [3, 4])
    tn = 0.2_wp     ! shell thickness 0.2: half-thickness 0.1
    call segment_check(sq, tn, .true., [0.3_wp, -0.2_wp, 0.5_wp], 0.05_wp, h)
    call check(abs(h%xi - 0.3_wp) < tol .and. abs(h%eta + 0.2_wp) < tol .and. h%kind == contact_interior, &
               'segment check: flat projection is (x, y)')
    call check(abs(h%d - 0.5_wp) < tol .and. .not. h%found, 'segment check: 0.5 above a 0.2 shell is no contact')
    call segment_check(sq, tn, .true., [0.3_wp, -0.2_wp, 0.1_wp], 0.05_wp, h)
    call check(h%found .and. abs(h%a + 0.05_wp) < tol .and. all(abs(h%nhat - [0.0_wp, 0.0_wp, 1.0_wp]) < tol) &
               .and. h%level == 1, 'segment check: shell from above: a = d - (ts + tm) = -0.05, return +z (Eq. 11)')
    call segment_check(sq, tn, .true., [0.3_wp, -0.2_wp, -0.1_wp], 0.05_wp, h)
    ! Eq. (9) turns t to the side of n: the return direction is +z, and the
    ! force -K a n (Eq. 12, a > 0 here) pushes the slave down, out of the shell
    call check(h%found .and. abs(h%a - 0.05_wp) < tol .and. all(abs(h%nhat - [0.0_wp, 0.0_wp, 1.0_wp]) < tol), &
               'segment check: shell from below: a = +0.05, the force -K a n pushes down (shells are two-sided)')
    ! solid master, depth window tm = 0.3: contact for ts - tm <= d <= ts
    tn = 0.3_wp
    call segment_check(sq, tn, .false., [0.0_wp, 0.0_wp, -0.1_wp], 0.0_wp, h)
    call check(h%found .and. abs(h%a + 0.1_wp) < tol .and. all(abs(h%nhat - [0.0_wp, 0.0_wp, 1.0_wp]) < tol) &
               .and. h%level == 2, 'segment check: solid penetrated by 0.1: a = -0.1, return along the outward normal')
    call segment_check(sq, tn, .false., [0.0_wp, 0.0_wp, -0.35_wp], 0.0_wp, h)
    call check(.not. h%found, 'segment check: deeper than the solid window (Eq. 3, Fig. 7) is no contact')
    call segment_check(sq, tn, .false., [0.0_wp, 0.0_wp, 0.04_wp], 0.05_wp, h)
    call check(h%found .and. abs(h%a + 0.01_wp) < tol, 'segment check: shell slave (ts 0.05) 0.04 above a solid: a = -0.01')

    ! line contact beyond the edge x = 1, point contact beyond the corner
    tn = 0.2_wp
    call segment_check(sq, tn, .true., [1.5_wp, 0.2_wp, 0.1_wp], 0.5_wp, h)
    call check(h%kind == contact_line .and. abs(h%xi - 1) < tol .and. abs(h%eta - 0.2_wp) < tol .and. &
               abs(h%d - sqrt(0.26_wp)) < tol .and. h%found .and. h%level == 2, &
               'segment check: beyond an edge: line contact, tube distance sqrt(0.5^2 + 0.1^2)')
    call check(all(abs(h%nhat - [0.5_wp, 0.0_wp, 0.1_wp]/sqrt(0.26_wp)) < tol), &
               'segment check: tube return direction points from the edge to the slave')
    call segment_check(sq, tn, .true., [1.5_wp, 1.5_wp, 0.2_wp], 0.5_wp, h)
    call check(h%kind == contact_point .and. abs(h%xi - 1) < tol .and. abs(h%eta - 1) < tol .and. &
               abs(h%dist - sqrt(0.54_wp)) < tol, 'segment check: beyond a corner: point contact, pinball distance')

    ! warped segment z = c xi eta (exact on the bilinear patch x = xi, y = eta):
    ! a point on the surface normal through (0.3, 0.4) projects back to it
    c = 0.4_wp
    warp = sq
    warp(3, :) = c*[1.0_wp, -1.0_wp, 1.0_wp, -1.0_wp]
    s0 = [0.3_wp, 0.4_wp, c*0.12_wp]
    nrm = [-c*0.4_wp, -c*0.3_wp, 1.0_wp]
    nrm = nrm/norm2(nrm)
    p = s0 + 0.05_wp*nrm
    call segment_check(warp, tn, .true., p, 0.0_wp, h)
    call check(abs(h%xi - 0.3_wp) < 1.0e-9_wp .and. abs(h%eta - 0.4_wp) < 1.0e-9_wp .and. &
               abs(h%d - 0.05_wp) < 1.0e-9_wp, 'segment check: warped segment, Newton finds the foot of the normal')

    ! triangle (0,0), (2,0), (0,2): area coordinates of (0.5, 0.5) are 1/4, 1/4
    tri = reshape([0.0_wp, 0.0_wp, 0.0_wp, 2.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 2.0_wp, 0.0_wp, 0.0_wp, 2.0_wp, 0.0_wp], &
                  [3, 4])
    call segment_check(tri, tn, .true., [0.5_wp, 0.5_wp, 0.3_wp], 0.0_wp, h)
    call check(abs(h%xi - 0.25_wp) < tol .and. abs(h%eta - 0.25_wp) < tol .and. abs(h%d - 0.3_wp) < tol .and. &
               abs(sum(h%nshape) - 1) < tol .and. h%nshape(4) == 0, 'segment check: triangle, area coordinates')
    call segment_check(tri, tn, .true., [1.5_wp, 1.5_wp, 0.1_wp], 0.5_wp, h)
    call check(h%kind == contact_line .and. abs(h%xc(1) - 1) < tol .and. abs(h%xc(2) - 1) < tol, &
               'segment check: triangle, beyond the hypotenuse: line contact at its closest point')

    ! continuity across the shell edge x = 1: just inside and just outside
    call segment_check(sq, tn, .true., [1.0_wp - 1.0e-7_wp, 0.0_wp, 0.08_wp], 0.0_wp, h1)
    call segment_check(sq, tn, .true., [1.0_wp + 1.0e-7_wp, 0.0_wp, 0.08_wp], 0.0_wp, h2)
    call check(norm2(h1%nhat - h2%nhat) < 1.0e-5_wp .and. abs(h1%a - h2%a) < 1.0e-5_wp, &
               'segment check: return direction and penetration continuous across a shell edge')
    ! around the corner (1, 1): the pinball direction turns smoothly
    call segment_check(sq, tn, .true., [1.0_wp + 0.05_wp*cos(0.3_wp), 1.0_wp + 0.05_wp*sin(0.3_wp), 0.0_wp], 0.0_wp, h1)
    call segment_check(sq, tn, .true., [1.0_wp + 0.05_wp*cos(0.3001_wp), 1.0_wp + 0.05_wp*sin(0.3001_wp), 0.0_wp], &
                       0.0_wp, h2)
    call check(h1%kind == contact_point .and. norm2(h1%nhat - h2%nhat) < 2.0e-4_wp .and. &
               abs(h1%dist - 0.05_wp) < tol, 'segment check: pinball return direction continuous around a corner')
    call segment_check(sq, tn, .true., [0.9_wp, 0.0_wp, 0.05_wp], 0.0_wp, h)
    call check(h%near_node == 2 .or. h%near_node == 3, 'segment check: nearest node is on the x = 1 side')
    call check(h%near_border, 'segment check: 0.1 from the border with tm 0.1 is near the border')
    ! issue 16, (a): a shell slave in the plane of a master shell, beyond its
    ! edge (n . t = 0), is at the tube distance |t| along t, not on the
    ! segment (d = 0 made coplanar plates pass 10 mm into each other, and a
    ! flat plate of thick shells find contact with its own segments)
    tn = 0.2_wp
    call segment_check(sq, tn, .true., [1.05_wp, 0.2_wp, 0.0_wp], 0.1_wp, h)
    call check(h%kind == contact_line .and. h%found .and. abs(h%d - 0.05_wp) < tol .and. &
               abs(h%a + 0.15_wp) < tol .and. all(abs(h%nhat - [1.0_wp, 0.0_wp, 0.0_wp]) < tol), &
               'segment check: in-plane slave 0.05 beyond an edge: d = |t| = 0.05, a = -0.15, return along t (+x)')
    call segment_check(sq, tn, .true., [1.5_wp, 0.2_wp, 0.0_wp], 0.1_wp, h)
    call check(.not. h%found .and. abs(h%d - 0.5_wp) < tol, &
               'segment check: in-plane slave 0.5 beyond an edge of a 0.2 shell (ts 0.1) is no contact')
    call segment_check(sq, tn, .true., [1.1_wp, 1.1_wp, 0.0_wp], 0.1_wp, h)
    call check(h%kind == contact_point .and. h%found .and. abs(h%d - sqrt(0.02_wp)) < tol .and. &
               all(abs(h%nhat - [1.0_wp, 1.0_wp, 0.0_wp]/sqrt(2.0_wp)) < tol), &
               'segment check: in-plane slave beyond a corner: pinball distance and direction')
    ! issue 16, (b): both parametric coordinates out of range at an obtuse
    ! (150 degree) corner: the closest point is on an edge, not the corner
    call obtuse_corner()

    call test_summary()
contains

    subroutine obtuse_corner()
        real(wp) :: q(3, 4), pp(3), e(3), u, foot(3), dline, dcorner
        q = reshape([0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp + sqrt(3.0_wp)/2, 0.5_wp, 0.0_wp, &
                     0.0_wp, 1.0_wp, 0.0_wp], [3, 4])
        pp = [1.3_wp, -0.1_wp, 0.05_wp]
        e = q(:, 3) - q(:, 2)
        u = dot_product(pp - q(:, 2), e)/dot_product(e, e)
        foot = q(:, 2) + u*e
        dline = norm2(pp - foot)
        dcorner = norm2(pp - q(:, 2))
        call segment_check(q, [0.6_wp, 0.6_wp, 0.6_wp, 0.6_wp], .true., pp, 0.0_wp, h)
        call check(h%kind == contact_line .and. abs(h%dist - dline) < 1.0e-9_wp .and. dcorner - dline > 0.05_wp, &
                   'segment check: 150 degree corner, both coordinates out: closest point on the edge (distance ' &
                   //trim(fmt(dline))//' against the corner''s '//trim(fmt(dcorner))//')')
        call check(h%found .and. norm2(h%xc - foot) < 1.0e-9_wp, &
                   'segment check: 150 degree corner: contact point is the foot on the edge, the contact is found')
    end subroutine obtuse_corner

    function fmt(x) result(t)
        real(wp), intent(in) :: x
        character(len=16) :: t
        write (t, '(f8.4)') x
    end function fmt

end program test_contact_segment_check
